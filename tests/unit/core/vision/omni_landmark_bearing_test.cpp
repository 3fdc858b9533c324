// E2 measurement 3 from pixels: red cylinders drawn into a synthetic omni image through
// OmniCameraModel::project (over a textured floor and wall with noise) are found at their
// azimuth to 0.01 rad, also across the panorama's seam behind the robot; a red patch on the floor
// and a blue pole are not landmarks.
#include "core/vision/omni_landmark_bearing.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::vision {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kCameraHeight_m = 0.9;
constexpr double kCylinderRadius_m = 0.05;  // R1's landmark: d = 10 cm
const cv::Scalar kRed(35, 30, 200);
const cv::Scalar kBlue(190, 80, 40);

// Floor tiles (0.5 m) below the horizon, wall stripes above, all nearly grey; dark outside the
// mirror's ring, as the simulator renders it.
cv::Mat room(const OmniCameraModel& model) {
  cv::Mat image(model.height_px, model.width_px, CV_8UC3);
  for (int v = 0; v < image.rows; ++v) {
    for (int u = 0; u < image.cols; ++u) {
      const auto direction = model.direction({static_cast<double>(u), static_cast<double>(v)});
      cv::Vec3b colour(45, 45, 45);
      if (direction && direction->elevation_rad < 0.0) {
        const double range = kCameraHeight_m / std::tan(-direction->elevation_rad);
        const int tile =
            static_cast<int>(std::floor(range * std::cos(direction->azimuth_rad) / 0.5) +
                             std::floor(range * std::sin(direction->azimuth_rad) / 0.5));
        colour = (tile % 2 == 0) ? cv::Vec3b(150, 160, 170) : cv::Vec3b(105, 115, 125);
      } else if (direction) {
        const int stripe =
            static_cast<int>(std::floor((direction->azimuth_rad + kPi) / (7 * kDeg)));
        colour = (stripe % 2 == 0) ? cv::Vec3b(175, 178, 182) : cv::Vec3b(140, 150, 160);
      }
      image.at<cv::Vec3b>(v, u) = colour;
    }
  }
  return image;
}

// The outline of the region between two azimuths and two elevations, projected point by point.
std::vector<cv::Point> outline(const OmniCameraModel& model, double azimuth_lo, double azimuth_hi,
                               double elevation_lo, double elevation_hi) {
  constexpr int kShift = 4;
  constexpr int kSteps = 60;
  std::vector<cv::Point> points;
  const auto add = [&](double azimuth, double elevation) {
    const auto pixel = model.project({azimuth, elevation});
    if (!pixel) return;
    points.emplace_back(static_cast<int>(std::lround(pixel->u * (1 << kShift))),
                        static_cast<int>(std::lround(pixel->v * (1 << kShift))));
  };
  for (int i = 0; i <= kSteps; ++i) {
    add(azimuth_lo, elevation_lo + (elevation_hi - elevation_lo) * i / kSteps);
  }
  for (int i = 0; i <= kSteps; ++i)
    add(azimuth_lo + (azimuth_hi - azimuth_lo) * i / kSteps, elevation_hi);
  for (int i = 0; i <= kSteps; ++i) {
    add(azimuth_hi, elevation_hi - (elevation_hi - elevation_lo) * i / kSteps);
  }
  for (int i = 0; i <= kSteps; ++i)
    add(azimuth_hi - (azimuth_hi - azimuth_lo) * i / kSteps, elevation_lo);
  return points;
}

void fill(cv::Mat& image, const std::vector<cv::Point>& points, const cv::Scalar& colour) {
  const std::vector<std::vector<cv::Point>> polygons{points};
  cv::fillPoly(image, polygons, colour, cv::LINE_AA, 4);
}

// A vertical cylinder of R1's landmark at `azimuth`, `range_m` away: from -40 to +15 deg of
// elevation, as wide as the cylinder looks from there.
void draw_cylinder(const OmniCameraModel& model, cv::Mat& image, double azimuth, double range_m,
                   const cv::Scalar& colour = kRed) {
  const double half_width = std::asin(kCylinderRadius_m / range_m);
  fill(image, outline(model, azimuth - half_width, azimuth + half_width, -40 * kDeg, 15 * kDeg),
       colour);
}

void add_noise(cv::Mat& image, std::uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat noise(image.size(), CV_16SC3);
  rng.fill(noise, cv::RNG::NORMAL, 0, 6);
  cv::Mat wide;
  image.convertTo(wide, CV_16SC3);
  wide += noise;
  wide.convertTo(image, CV_8UC3);
}

class OmniLandmarkBearingTest : public ::testing::Test {
 protected:
  OmniLandmarkBearingTest() : detector_(model_), room_(room(model_)) {}

  cv::Mat scene_with(const std::vector<std::pair<double, double>>& cylinders,
                     std::uint64_t seed = 1) const {
    cv::Mat image = room_.clone();
    for (const auto& [azimuth, range] : cylinders) draw_cylinder(model_, image, azimuth, range);
    add_noise(image, seed);
    return image;
  }

  OmniCameraModel model_;
  OmniLandmarkBearingDetector detector_;
  cv::Mat room_;
};

TEST_F(OmniLandmarkBearingTest, FindsOneCylinderAtItsAzimuthAllAround) {
  const std::vector<double> azimuths{0.0,  0.3,  0.7,  1.5,         2.4,          3.0,
                                     -0.9, -2.0, -3.0, kPi - 0.005, -kPi + 0.012, kPi};
  std::uint64_t seed = 1;
  for (const double azimuth : azimuths) {
    const OmniLandmarkDetection detection = detector_.detect(scene_with({{azimuth, 2.0}}, ++seed));
    ASSERT_FALSE(detection.error.has_value());
    ASSERT_EQ(detection.landmarks.size(), 1U) << "azimuth " << azimuth;
    const LandmarkBearing& found = detection.landmarks.front();
    EXPECT_LT(std::abs(geometry::wrap_angle(found.bearing_rad - azimuth)), 0.01)
        << "azimuth " << azimuth << " found " << found.bearing_rad;
    EXPECT_GT(found.bearing_rad, -kPi);
    EXPECT_LE(found.bearing_rad, kPi);
    EXPECT_GT(found.extent_rad, 40 * kDeg);
    EXPECT_GT(found.support_px, 200);
  }
}

TEST_F(OmniLandmarkBearingTest, NearAndFarCylindersAlike) {
  for (const double range : {0.6, 1.0, 3.0, 5.0}) {
    const double azimuth = 0.9;
    const OmniLandmarkDetection detection = detector_.detect(scene_with({{azimuth, range}}, 7));
    ASSERT_EQ(detection.landmarks.size(), 1U) << "range " << range;
    const LandmarkBearing& found = detection.landmarks.front();
    EXPECT_LT(std::abs(geometry::wrap_angle(found.bearing_rad - azimuth)), 0.01) << range;
    // The width follows the range: 2 asin(r / range), give or take a column.
    EXPECT_NEAR(found.width_rad, 2.0 * std::asin(kCylinderRadius_m / range), 0.02) << range;
  }
}

TEST_F(OmniLandmarkBearingTest, AFarCylinderIsShortAndThinButFound) {
  // R1's 1.5 m cylinder 8 m away: 11 deg tall, 0.0125 rad (1.4 columns) wide.
  cv::Mat image = room_.clone();
  const double half_width = std::asin(kCylinderRadius_m / 8.0);
  fill(image,
       outline(model_, -0.4 - half_width, -0.4 + half_width, -std::atan(kCameraHeight_m / 8.0),
               std::atan((1.5 - kCameraHeight_m) / 8.0)),
       kRed);
  add_noise(image, 8);
  const OmniLandmarkDetection detection = detector_.detect(image);
  ASSERT_EQ(detection.landmarks.size(), 1U);
  EXPECT_LT(std::abs(detection.landmarks.front().bearing_rad + 0.4), 0.01);
}

TEST_F(OmniLandmarkBearingTest, TwoLandmarksAtOnce) {
  const OmniLandmarkDetection detection =
      detector_.detect(scene_with({{0.5, 1.5}, {-2.2, 3.0}}, 9));
  ASSERT_EQ(detection.landmarks.size(), 2U);
  // Strongest first: the nearer one is wider.
  EXPECT_LT(std::abs(detection.landmarks[0].bearing_rad - 0.5), 0.01);
  EXPECT_LT(std::abs(detection.landmarks[1].bearing_rad + 2.2), 0.01);
  EXPECT_GT(detection.landmarks[0].support_px, detection.landmarks[1].support_px);
}

TEST_F(OmniLandmarkBearingTest, TwoLandmarksEitherSideOfTheSeam) {
  const OmniLandmarkDetection detection =
      detector_.detect(scene_with({{kPi - 0.08, 2.0}, {-kPi + 0.08, 2.0}}, 10));
  ASSERT_EQ(detection.landmarks.size(), 2U);
  std::vector<double> bearings{detection.landmarks[0].bearing_rad,
                               detection.landmarks[1].bearing_rad};
  std::sort(bearings.begin(), bearings.end());
  EXPECT_NEAR(bearings[0], -kPi + 0.08, 0.01);
  EXPECT_NEAR(bearings[1], kPi - 0.08, 0.01);
}

TEST_F(OmniLandmarkBearingTest, NoRedNoLandmark) {
  const OmniLandmarkDetection detection = detector_.detect(scene_with({}, 11));
  EXPECT_FALSE(detection.error.has_value());
  EXPECT_TRUE(detection.landmarks.empty());
}

TEST_F(OmniLandmarkBearingTest, ARedPatchOnTheFloorAndABluePoleAreNotLandmarks) {
  cv::Mat image = room_.clone();
  // A 0.3 m red mat 1 m away: wider than tall in the panorama.
  fill(image,
       outline(model_, 1.0 - 0.15, 1.0 + 0.15, -std::atan(kCameraHeight_m / 0.85),
               -std::atan(kCameraHeight_m / 1.15)),
       kRed);
  draw_cylinder(model_, image, -1.2, 1.5, kBlue);
  draw_cylinder(model_, image, 2.5, 2.0);
  add_noise(image, 12);
  const OmniLandmarkDetection detection = detector_.detect(image);
  ASSERT_EQ(detection.landmarks.size(), 1U);
  EXPECT_LT(std::abs(detection.landmarks.front().bearing_rad - 2.5), 0.01);
}

TEST_F(OmniLandmarkBearingTest, AShortRedStubIsNotALandmark) {
  cv::Mat image = room_.clone();
  // A red box on the floor, 5 deg tall: too short for a landmark however narrow.
  fill(image, outline(model_, 0.4 - 0.01, 0.4 + 0.01, -30 * kDeg, -25 * kDeg), kRed);
  add_noise(image, 13);
  EXPECT_TRUE(detector_.detect(image).landmarks.empty());
}

TEST_F(OmniLandmarkBearingTest, RefusesBadFrames) {
  EXPECT_EQ(detector_.detect(cv::Mat()).error, OmniFrameError::kInvalidFrame);
  EXPECT_EQ(detector_.detect(cv::Mat(480, 480, CV_8UC1, cv::Scalar(0))).error,
            OmniFrameError::kInvalidFrame);
  EXPECT_EQ(detector_.detect(cv::Mat(480, 640, CV_8UC3, cv::Scalar::all(0))).error,
            OmniFrameError::kFrameSizeMismatch);
  EXPECT_TRUE(detector_.unwarp(cv::Mat()).empty());
  EXPECT_EQ(error_code(OmniFrameError::kFrameSizeMismatch), "frame_size_mismatch");
}

TEST_F(OmniLandmarkBearingTest, ColumnAzimuthMapping) {
  const double step = 2 * kPi / 720;
  EXPECT_NEAR(detector_.azimuth_of_column_rad(0.0), kPi - 0.5 * step, 1e-12);
  EXPECT_NEAR(detector_.azimuth_of_column_rad(359.5), 0.0, 1e-12);  // the heading, mid-panorama
  EXPECT_NEAR(detector_.azimuth_of_column_rad(719.0), -kPi + 0.5 * step, 1e-12);
  EXPECT_GT(detector_.azimuth_of_column_rad(100.0), 0.0);  // left half: the robot's left
  for (const double azimuth : {-3.0, -1.0, 0.0, 0.5, 2.9, kPi}) {
    EXPECT_NEAR(detector_.azimuth_of_column_rad(detector_.column_of_azimuth_px(azimuth)), azimuth,
                1e-12);
  }
  EXPECT_NEAR(detector_.elevation_of_row_rad(-0.5), 20 * kDeg, 1e-12);
  EXPECT_NEAR(detector_.elevation_of_row_rad(159.5), -60 * kDeg, 1e-12);
}

TEST_F(OmniLandmarkBearingTest, UnwarpPutsTheCylinderInItsColumn) {
  const cv::Mat panorama = detector_.unwarp(scene_with({{0.0, 1.0}}, 14));
  ASSERT_EQ(panorama.size(), cv::Size(720, 160));
  // The heading's column at the horizon is red, the opposite one is not.
  const int horizon_row = static_cast<int>(std::lround(20.0 / 80.0 * 160 - 0.5));
  const cv::Vec3b ahead = panorama.at<cv::Vec3b>(horizon_row, 360);
  const cv::Vec3b behind = panorama.at<cv::Vec3b>(horizon_row, 0);
  EXPECT_GT(ahead[2], 150);
  EXPECT_LT(ahead[0], 90);
  EXPECT_LT(behind[2], 200);
  EXPECT_GT(behind[0], 100);
}

TEST(OmniLandmarkBearingOptions, RejectsBadOptions) {
  const OmniCameraModel model;
  OmniLandmarkBearingOptions band;
  band.min_elevation_rad = 0.5;
  band.max_elevation_rad = 0.1;
  EXPECT_THROW(OmniLandmarkBearingDetector(model, band), std::invalid_argument);
  OmniLandmarkBearingOptions hue;
  hue.hue_centre = 180;
  EXPECT_THROW(OmniLandmarkBearingDetector(model, hue), std::invalid_argument);
  OmniCameraModel empty;
  empty.width_px = 0;
  EXPECT_THROW(OmniLandmarkBearingDetector{empty}, std::invalid_argument);
}

}  // namespace
}  // namespace mobot::vision
