#include "drivers/sim/camera_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <stdexcept>
#include <vector>

#include "tests/unit/drivers/sim/sim_test_support.h"

namespace mobot::sim {
namespace {

using testing::empty_world;
using testing::fill_cells;
using testing::outer_walls;

constexpr RgbColor kRed{220, 30, 30};

// A 12 x 12 m room at 0.05 m with nothing in it.
World room() {
  World world = empty_world(240, 240, 0.05);
  outer_walls(world.floor);
  return world;
}

// A renderable scene and what it borrows.
struct Stage {
  World world = room();
  std::optional<RayCaster> walls;
  std::vector<SceneCylinder> obstacles;
  std::vector<SceneSphere> targets;

  CameraScene scene() {
    walls.emplace(world.floor);
    return {world, *walls, obstacles, targets, {}};
  }
};

// Red as a hue tracker sees it: OpenCV hue within 10 of 0, well saturated and not dark.
cv::Mat red_mask(const cv::Mat& bgr) {
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  cv::Mat low;
  cv::Mat high;
  cv::inRange(hsv, cv::Scalar(0, 120, 50), cv::Scalar(10, 255, 255), low);
  cv::inRange(hsv, cv::Scalar(170, 120, 50), cv::Scalar(180, 255, 255), high);
  return low | high;
}

std::optional<cv::Point2d> centroid(const cv::Mat& mask) {
  const cv::Moments m = cv::moments(mask, true);
  if (m.m00 < 1.0) return std::nullopt;
  return cv::Point2d{m.m10 / m.m00, m.m01 / m.m00};
}

// The pinhole projection written out from the camera's rotation matrix (camera x right, y down,
// z forward), independently of the renderer's ray construction.
cv::Point2d project(const vision::CameraPose& pose, const vision::PinholeCamera& camera, double x_m,
                    double y_m, double z_m) {
  const double cy = std::cos(pose.yaw_rad);
  const double sy = std::sin(pose.yaw_rad);
  const double cp = std::cos(pose.pitch_rad);
  const double sp = std::sin(pose.pitch_rad);
  const cv::Matx33d world_to_camera(sy, -cy, 0.0,           // right
                                    sp * cy, sp * sy, -cp,  // down
                                    cp * cy, cp * sy, sp);  // forward
  const cv::Vec3d p = world_to_camera * cv::Vec3d(x_m - pose.x_m, y_m - pose.y_m, z_m - pose.z_m);
  const double f = camera.focal_px();
  return {0.5 * camera.width_px + f * p[0] / p[2], 0.5 * camera.height_px + f * p[1] / p[2]};
}

cv::Mat perspective(Stage& stage, const vision::CameraPose& pose,
                    const CameraNoise& noise = CameraNoise::none(), std::uint64_t seed = 1) {
  std::mt19937_64 rng(seed);
  const vision::PinholeCamera camera;
  return render_perspective(stage.scene(), pose, camera, noise, rng);
}

TEST(CameraRenderer, ATargetAppearsWhereThePinholeProjectsIt) {
  const vision::PinholeCamera camera;
  const std::vector<vision::CameraPose> poses = {
      {1.0, 6.0, 1.0, 0.0, 0.0},
      {1.0, 6.0, 1.2, 0.25, -0.15},
      {2.0, 3.0, 0.6, 0.9, 0.2},
      {10.0, 10.0, 1.5, -2.4, -0.2},
  };
  for (const vision::CameraPose& pose : poses) {
    Stage stage;
    // 4 m ahead, a little to the left of and below the optical axis (and above the floor, which
    // would hide its lower half).
    const double x_m = pose.x_m + 4.0 * std::cos(pose.yaw_rad + 0.15);
    const double y_m = pose.y_m + 4.0 * std::sin(pose.yaw_rad + 0.15);
    const double z_m = pose.z_m + 4.0 * std::tan(pose.pitch_rad) - 0.2;
    stage.targets = {{x_m, y_m, z_m, 0.15, kRed}};
    const auto seen = centroid(red_mask(perspective(stage, pose, CameraNoise())));
    ASSERT_TRUE(seen) << "yaw " << pose.yaw_rad;
    const cv::Point2d expected = project(pose, camera, x_m, y_m, z_m);
    EXPECT_NEAR(seen->x, expected.x, 2.0) << "yaw " << pose.yaw_rad;
    EXPECT_NEAR(seen->y, expected.y, 2.0) << "yaw " << pose.yaw_rad;
  }
}

TEST(CameraRenderer, AWallHidesATargetBehindIt) {
  const vision::CameraPose pose{1.0, 6.0, 1.0, 0.0, 0.0};
  Stage open;
  open.targets = {{5.0, 6.0, 0.8, 0.15, kRed}};
  ASSERT_GT(cv::countNonZero(red_mask(perspective(open, pose))), 100);

  Stage walled = open;
  fill_cells(walled.world.floor, 60, 100, 61, 140);  // x 3.0-3.1 m, y 5-7 m
  EXPECT_EQ(cv::countNonZero(red_mask(perspective(walled, pose))), 0);
}

TEST(CameraRenderer, AnObstacleHidesATargetBehindItAndNotBeside) {
  const vision::CameraPose pose{1.0, 6.0, 1.0, 0.0, 0.0};
  Stage stage;
  stage.targets = {{5.0, 6.0, 0.8, 0.15, kRed}};
  stage.obstacles = {{3.0, 6.0, 0.3, 1.5}};
  EXPECT_EQ(cv::countNonZero(red_mask(perspective(stage, pose))), 0);
  // Walking out from behind the pillar it shows again; and in front of it, over it.
  stage.targets = {{5.0, 7.5, 0.8, 0.15, kRed}};
  EXPECT_GT(cv::countNonZero(red_mask(perspective(stage, pose))), 100);
  stage.targets = {{2.0, 6.0, 0.8, 0.15, kRed}};
  EXPECT_GT(cv::countNonZero(red_mask(perspective(stage, pose))), 1000);
}

TEST(CameraRenderer, AShortObstacleDoesNotHideATargetAboveIt) {
  const vision::CameraPose pose{1.0, 6.0, 1.0, 0.0, 0.0};
  Stage stage;
  stage.targets = {{5.0, 6.0, 1.0, 0.15, kRed}};
  stage.obstacles = {{3.0, 6.0, 0.3, 0.5}};
  EXPECT_GT(cv::countNonZero(red_mask(perspective(stage, pose))), 100);
}

TEST(CameraRenderer, ABoxHidesATargetBehindItAndATargetBehindTheCameraIsNotDrawn) {
  const vision::CameraPose pose{1.0, 6.0, 1.0, 0.0, 0.0};
  Stage stage;
  stage.world.boxes = {{3.0, 5.5, 3.4, 6.5, 0.0, 1.2, "cabinet", false}};
  stage.targets = {{5.0, 6.0, 0.8, 0.15, kRed}};
  EXPECT_EQ(cv::countNonZero(red_mask(perspective(stage, pose))), 0);
  stage.world.boxes.clear();
  stage.targets = {{0.5, 6.0, 1.0, 0.15, kRed}};
  EXPECT_EQ(cv::countNonZero(red_mask(perspective(stage, pose))), 0);
}

TEST(CameraRenderer, LooksStraightDownAndUpWithoutGaps) {
  Stage stage;
  stage.targets = {{6.0, 6.0, 0.2, 0.15, kRed}};
  for (const double pitch_rad : {-std::numbers::pi / 2, std::numbers::pi / 2, -1.3}) {
    const cv::Mat image = perspective(stage, {6.0, 6.0, 1.2, 0.4, pitch_rad});
    // No pixel left at the black the image starts as.
    cv::Mat grey;
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
    double darkest = 0.0;
    cv::minMaxLoc(grey, &darkest);
    EXPECT_GT(darkest, 20.0) << "pitch " << pitch_rad;
  }
  // The ball right below the camera is in the middle of the downward view.
  const auto seen =
      centroid(red_mask(perspective(stage, {6.0, 6.0, 1.2, 0.4, -std::numbers::pi / 2})));
  ASSERT_TRUE(seen);
  EXPECT_NEAR(seen->x, 320.0, 2.0);
  EXPECT_NEAR(seen->y, 240.0, 2.0);
}

TEST(CameraRenderer, PitchingUpMovesATargetDown) {
  Stage stage;
  stage.targets = {{5.0, 6.0, 1.0, 0.15, kRed}};
  vision::CameraPose pose{1.0, 6.0, 1.0, 0.0, -0.1};
  const auto level = centroid(red_mask(perspective(stage, pose)));
  pose.pitch_rad = 0.1;
  const auto up = centroid(red_mask(perspective(stage, pose)));
  ASSERT_TRUE(level && up);
  EXPECT_GT(up->y, level->y + 50.0);
  EXPECT_NEAR(up->x, level->x, 1.0);
}

TEST(CameraRenderer, TheFloorIsBelowTheHorizonAndTheCeilingAbove) {
  Stage stage;
  const cv::Mat image = perspective(stage, {6.0, 6.0, 1.0, 0.3, 0.0});
  // Looking level from 1 m at a wall 4-6 m away: the bottom rows are floor, the top rows ceiling
  // (brighter), the middle wall.
  const cv::Scalar bottom = cv::mean(image.rowRange(470, 480));
  const cv::Scalar top = cv::mean(image.rowRange(0, 10));
  EXPECT_GT(top[1], bottom[1] + 30.0);
}

// The red pixels' mean direction around the omni image's centre, read through the model.
std::optional<double> mean_red_azimuth(const cv::Mat& image, const vision::OmniCameraModel& model) {
  const cv::Mat mask = red_mask(image);
  double sum_cos = 0.0;
  double sum_sin = 0.0;
  int count = 0;
  for (int v = 0; v < mask.rows; ++v) {
    for (int u = 0; u < mask.cols; ++u) {
      if (mask.at<std::uint8_t>(v, u) == 0) continue;
      const auto direction = model.direction({1.0 * u, 1.0 * v});
      if (!direction) continue;
      sum_cos += std::cos(direction->azimuth_rad);
      sum_sin += std::sin(direction->azimuth_rad);
      ++count;
    }
  }
  if (count < 20) return std::nullopt;
  return std::atan2(sum_sin, sum_cos);
}

TEST(CameraRenderer, TheOmniImageShowsALandmarkAtItsBearing) {
  const vision::OmniCameraModel model;
  struct Case {
    geometry::Pose2D robot;
    double landmark_x_m;
    double landmark_y_m;
  };
  const std::vector<Case> cases = {
      {{6.0, 6.0, 0.0}, 9.0, 6.0},                // ahead
      {{6.0, 6.0, 0.0}, 6.0, 9.0},                // left
      {{6.0, 6.0, 0.7}, 2.0, 8.5},                // behind on the left
      {{6.0, 6.0, 1.3}, 4.0, 2.5},                // behind on the right
      {{6.0, 6.0, 0.0}, 2.0, 6.05},               // behind, a hair to the right of +pi
      {{6.0, 6.0, 0.0}, 2.0, 5.95},               // behind, a hair to the left of -pi
      {{6.0, 6.0, std::numbers::pi}, 9.0, 6.02},  // ahead while facing -x
  };
  for (const Case& c : cases) {
    Stage stage;
    stage.world.landmarks = {{"lm", c.landmark_x_m, c.landmark_y_m}};
    std::mt19937_64 rng(3);
    const cv::Mat image = render_omni(stage.scene(), c.robot, 1.0, model, CameraNoise(), rng);
    const double expected = geometry::wrap_angle(
        std::atan2(c.landmark_y_m - c.robot.y, c.landmark_x_m - c.robot.x) - c.robot.theta);
    const auto seen = mean_red_azimuth(image, model);
    ASSERT_TRUE(seen) << "landmark " << c.landmark_x_m << ", " << c.landmark_y_m;
    EXPECT_NEAR(geometry::wrap_angle(*seen - expected), 0.0, 0.02)
        << "landmark " << c.landmark_x_m << ", " << c.landmark_y_m << " expected " << expected;
  }
}

TEST(CameraRenderer, TheOmniImageIsDarkOutsideTheMirrorRing) {
  Stage stage;
  const vision::OmniCameraModel model;
  std::mt19937_64 rng(1);
  const cv::Mat image =
      render_omni(stage.scene(), {6.0, 6.0, 0.0}, 1.0, model, CameraNoise::none(), rng);
  const auto grey = [&image](int u, int v) {
    const cv::Vec3b& pixel = image.at<cv::Vec3b>(v, u);
    return (pixel[0] + pixel[1] + pixel[2]) / 3;
  };
  EXPECT_LT(grey(240, 240), 40);  // the centre disc: the camera itself
  EXPECT_LT(grey(2, 2), 40);      // a corner beyond the mirror's rim
  EXPECT_LT(grey(477, 477), 40);
  EXPECT_GT(grey(240, 240 - 100), 60);  // inside the ring: the floor or a wall
}

TEST(CameraRenderer, AWallHidesALandmarkFromTheOmniCamera) {
  const vision::OmniCameraModel model;
  Stage stage;
  stage.world.landmarks = {{"lm", 10.0, 6.0}};
  fill_cells(stage.world.floor, 160, 100, 161, 140);  // x 8.0-8.1 m, y 5-7 m
  std::mt19937_64 rng(1);
  const cv::Mat image =
      render_omni(stage.scene(), {6.0, 6.0, 0.0}, 1.0, model, CameraNoise::none(), rng);
  EXPECT_EQ(cv::countNonZero(red_mask(image)), 0);
}

TEST(CameraRenderer, TheSameSeedGivesTheSameImageAndAnotherSeedOtherNoise) {
  Stage stage;
  stage.targets = {{5.0, 6.0, 0.8, 0.15, kRed}};
  const vision::CameraPose pose{1.0, 6.0, 1.0, 0.0, 0.0};
  const CameraNoise noise;
  const cv::Mat first = perspective(stage, pose, noise, 7);
  const cv::Mat again = perspective(stage, pose, noise, 7);
  const cv::Mat other = perspective(stage, pose, noise, 8);
  EXPECT_EQ(cv::norm(first, again, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(first, other, cv::NORM_L1), 1e5);

  const vision::OmniCameraModel model;
  std::mt19937_64 rng_a(7);
  std::mt19937_64 rng_b(7);
  const cv::Mat omni_a = render_omni(stage.scene(), {6.0, 6.0, 0.0}, 1.0, model, noise, rng_a);
  const cv::Mat omni_b = render_omni(stage.scene(), {6.0, 6.0, 0.0}, 1.0, model, noise, rng_b);
  EXPECT_EQ(cv::norm(omni_a, omni_b, cv::NORM_INF), 0.0);
}

TEST(CameraRenderer, TheTargetStaysRedThroughLightingDriftAndNoise) {
  Stage stage;
  stage.targets = {{5.0, 6.0, 0.8, 0.15, kRed}};
  const vision::CameraPose pose{1.0, 6.0, 1.0, 0.0, 0.0};
  const int clean = cv::countNonZero(red_mask(perspective(stage, pose)));
  // A strong drift: the gain wanders over about 0.6..1.4.
  CameraNoise noise({0.2, 2.0, 4.0, 0.7});
  std::mt19937_64 rng(5);
  noise.start(rng);
  for (int frame = 0; frame < 10; ++frame) {
    noise.advance(2.0, rng);
    const cv::Mat image =
        render_perspective(stage.scene(), pose, vision::PinholeCamera{}, noise, rng);
    EXPECT_NEAR(cv::countNonZero(red_mask(image)), clean, 0.25 * clean) << "gain " << noise.gain();
  }
}

TEST(CameraRenderer, RejectsABadCameraOrPose) {
  Stage stage;
  std::mt19937_64 rng(1);
  const CameraNoise noise;
  const CameraScene scene = stage.scene();
  vision::PinholeCamera wide;
  wide.horizontal_fov_rad = std::numbers::pi;
  EXPECT_THROW(render_perspective(scene, {}, wide, noise, rng), std::invalid_argument);
  vision::PinholeCamera empty;
  empty.width_px = 0;
  EXPECT_THROW(render_perspective(scene, {}, empty, noise, rng), std::invalid_argument);
  EXPECT_THROW(render_perspective(scene, {std::nan(""), 0.0, 1.0, 0.0, 0.0},
                                  vision::PinholeCamera{}, noise, rng),
               std::invalid_argument);
  vision::OmniCameraModel flat;
  flat.max_elevation_rad = 1.2;  // sin(1.2) > xi: the ring would reach infinity
  EXPECT_THROW(render_omni(scene, {}, 1.0, flat, noise, rng), std::invalid_argument);
  EXPECT_THROW(render_omni(scene, {}, std::nan(""), vision::OmniCameraModel{}, noise, rng),
               std::invalid_argument);
}

}  // namespace
}  // namespace mobot::sim
