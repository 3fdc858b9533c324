// E2's measurement 3 from pixels: an omni frame rendered in the office, handed to the stage as the
// camera's JPEG, comes back as bearings matched to the office's landmarks, within the bearing
// noise the EKF assumes (0.017 rad), while a pose estimate off by more than the gate matches none.
#include "server/stages/omni_bearing_stage.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <thread>

#include "drivers/sim/camera_renderer.h"
#include "drivers/sim/world.h"

namespace mobot::server {
namespace {

struct Scene {
  sim::World world = sim::load_world(std::string(MOBOT_DEFAULT_WORLDS_DIR) + "/office/world.yaml");
  sim::RayCaster walls{world.floor};
  vision::OmniCameraModel model;

  msgs::Image frame(const geometry::Pose2D& pose, double stamp_s) const {
    std::mt19937_64 rng(7);
    const cv::Mat bgr = sim::render_omni({world, walls, {}, {}, {}}, pose, 1.0, model,
                                         sim::CameraNoise(), rng);
    msgs::Image image;
    image.stamp_s = stamp_s;
    image.encoding = "jpeg";
    image.width = bgr.cols;
    image.height = bgr.rows;
    cv::imencode(".jpg", bgr, image.data, {cv::IMWRITE_JPEG_QUALITY, 85});
    return image;
  }
  std::vector<drivers::LandmarkSpot> spots() const {
    std::vector<drivers::LandmarkSpot> out;
    for (const auto& l : world.landmarks) out.push_back({l.name, {l.x_m, l.y_m}});
    return out;
  }
};

// Steps the stage until it hands out bearings (the detector works on its own thread).
std::optional<msgs::LandmarkBearings> run_until_bearings(OmniBearingStage& stage, Bus& bus,
                                                         const msgs::Image& image,
                                                         const geometry::Pose2D& estimate) {
  TickContext context(bus);
  for (int tick = 0; tick < 200; ++tick) {
    context.begin(0.02 * tick, 0.02);
    context.pose = estimate;
    if (tick == 0) context.image = image;
    stage.step(context);
    if (context.bearings) return context.bearings;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return std::nullopt;
}

TEST(OmniBearingStage, FindsTheLandmarksInThePixelsAndNamesThem) {
  const Scene scene;
  // In the main corridor, facing east: the corridor's two end landmarks are in sight.
  const geometry::Pose2D truth{4.0, 7.6, 0.3};
  OmniBearingStage stage(scene.model, scene.spots(), 20.0);
  Bus bus;
  const auto bearings = run_until_bearings(stage, bus, scene.frame(truth, 0.0), truth);
  ASSERT_TRUE(bearings.has_value());
  ASSERT_FALSE(bearings->bearings.empty());
  for (const msgs::LandmarkBearing& seen : bearings->bearings) {
    const double expected = geometry::wrap_angle(
        std::atan2(seen.landmark_in_map.y - truth.y, seen.landmark_in_map.x - truth.x) -
        truth.theta);
    EXPECT_NEAR(geometry::wrap_angle(seen.bearing_rad - expected), 0.0, 0.017) << seen.name;
    EXPECT_FALSE(seen.range_m.has_value());
  }
}

TEST(OmniBearingStage, AnEstimateOffByMoreThanTheGateMatchesNothing) {
  const Scene scene;
  const geometry::Pose2D truth{4.0, 7.6, 0.3};
  OmniBearingStage stage(scene.model, scene.spots(), 20.0, 0.1);
  Bus bus;
  // Heading off by 0.5 rad: every predicted bearing is 0.5 rad from what the pixels show.
  const auto bearings =
      run_until_bearings(stage, bus, scene.frame(truth, 0.0), {truth.x, truth.y, truth.theta + 0.5});
  EXPECT_FALSE(bearings.has_value());
}

}  // namespace
}  // namespace mobot::server
