// The simulated omnidirectional camera: Simulator::read_landmark_bearings (docs/algorithms.md E2
// set 3).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "drivers/sim/simulator.h"
#include "tests/unit/drivers/sim/sim_test_support.h"

namespace mobot::sim {
namespace {

using testing::fill_cells;

constexpr double kPi = std::numbers::pi;

// R1 without wheel errors and with an exact camera.
RobotProfile exact_camera_profile() {
  RobotProfile profile = r1_profile();
  profile.left_wheel_scale = 1.0;
  profile.right_wheel_scale = 1.0;
  profile.track_scale = 1.0;
  profile.wheel_speed_noise_fraction = 0.0;
  profile.bearing_sigma_rad = 0.0;
  return profile;
}

// 10 x 10 m at 0.05 m, closed, split by a wall at x 5.0..5.1 m. The robot stands at (3, 5).
World walled_world(std::vector<Landmark> landmarks) {
  World world = testing::empty_world(200, 200, 0.05);
  testing::outer_walls(world.floor);
  fill_cells(world.floor, 100, 0, 101, 199);
  world.start = {3.0, 5.0, 0.0};
  world.landmarks = std::move(landmarks);
  return world;
}

const msgs::LandmarkBearing* find(const msgs::LandmarkBearings& seen, const std::string& name) {
  for (const auto& bearing : seen.bearings) {
    if (bearing.name == name) return &bearing;
  }
  return nullptr;
}

std::vector<std::string> names(const msgs::LandmarkBearings& seen) {
  std::vector<std::string> out;
  for (const auto& bearing : seen.bearings) out.push_back(bearing.name);
  return out;
}

TEST(LandmarkBearings, R1ProfileHasTheMeasuredCameraNoise) {
  const RobotProfile profile = r1_profile();
  EXPECT_DOUBLE_EQ(profile.camera_range_m, 8.0);
  EXPECT_NEAR(profile.bearing_sigma_rad * profile.bearing_sigma_rad, 2.992e-4, 1e-12);
}

TEST(LandmarkBearings, BearingIsTheDirectionFromTheCentreRelativeToTheHeading) {
  const std::vector<Landmark> landmarks{
      {"ahead_left", 4.5, 6.0}, {"behind", 0.5, 4.9}, {"right", 3.2, 1.0}, {"left", 2.0, 9.0}};
  Simulator sim(walled_world(landmarks), exact_camera_profile(), 3);
  for (const geometry::Pose2D pose :
       {geometry::Pose2D{3.0, 5.0, 0.0}, geometry::Pose2D{3.0, 5.0, 0.3},
        geometry::Pose2D{2.5, 4.0, -2.9}, geometry::Pose2D{1.5, 6.0, kPi}}) {
    sim.reset(pose, 3);
    const msgs::LandmarkBearings seen = sim.read_landmark_bearings();
    ASSERT_EQ(seen.bearings.size(), landmarks.size());
    for (std::size_t i = 0; i < landmarks.size(); ++i) {
      const msgs::LandmarkBearing& bearing = seen.bearings[i];
      EXPECT_EQ(bearing.name, landmarks[i].name);  // in the world's order
      EXPECT_EQ(bearing.landmark_in_map, (geometry::Point2D{landmarks[i].x_m, landmarks[i].y_m}));
      const double expected = geometry::wrap_angle(
          std::atan2(landmarks[i].y_m - pose.y, landmarks[i].x_m - pose.x) - pose.theta);
      EXPECT_NEAR(bearing.bearing_rad, expected, 1e-12) << bearing.name;
      EXPECT_GT(bearing.bearing_rad, -kPi);
      EXPECT_LE(bearing.bearing_rad, kPi);
    }
  }
  // Straight ahead after driving: the stamp follows the simulator's clock.
  sim.reset({3.0, 6.0, 0.0}, 3);
  sim.set_command({0.5, 0.0});
  for (int i = 0; i < 50; ++i) sim.step(0.02);
  const msgs::LandmarkBearings seen = sim.read_landmark_bearings();
  EXPECT_DOUBLE_EQ(seen.stamp_s, 1.0);
  const geometry::Pose2D pose = sim.true_pose();
  ASSERT_NE(find(seen, "ahead_left"), nullptr);
  EXPECT_NEAR(find(seen, "ahead_left")->bearing_rad,
              std::atan2(6.0 - pose.y, 4.5 - pose.x) - pose.theta, 1e-12);
}

TEST(LandmarkBearings, AWallHidesALandmarkBehindIt) {
  Simulator sim(walled_world({{"this_side", 4.0, 7.0},
                              {"other_side", 7.0, 5.0},
                              {"against_the_wall", 4.95, 3.0},  // 5 cm from the wall face
                              {"far_side_of_wall", 5.15, 3.0}}),
                exact_camera_profile(), 1);
  EXPECT_EQ(names(sim.read_landmark_bearings()),
            (std::vector<std::string>{"this_side", "against_the_wall"}));
  // From the other room the view is the other way round.
  sim.reset({7.0, 3.0, 0.0}, 1);
  EXPECT_EQ(names(sim.read_landmark_bearings()),
            (std::vector<std::string>{"other_side", "far_side_of_wall"}));
}

TEST(LandmarkBearings, TallObstaclesOccludeLowOnesDoNot) {
  Simulator sim(walled_world({{"lm", 4.5, 5.0}}), exact_camera_profile(), 1);
  ASSERT_EQ(sim.read_landmark_bearings().bearings.size(), 1U);
  const int low = sim.add_obstacle(3.8, 5.0, 0.1, 0.2);  // below the laser plane (0.4 m)
  EXPECT_EQ(sim.read_landmark_bearings().bearings.size(), 1U);
  const int tall = sim.add_obstacle(3.8, 5.05, 0.1, 1.0);
  EXPECT_TRUE(sim.read_landmark_bearings().bearings.empty());
  EXPECT_TRUE(sim.remove_obstacle(tall));
  EXPECT_EQ(sim.read_landmark_bearings().bearings.size(), 1U);
  EXPECT_TRUE(sim.remove_obstacle(low));
  // An obstacle beside the line of sight does not hide it.
  sim.add_obstacle(3.8, 5.5, 0.1, 1.0);
  EXPECT_EQ(sim.read_landmark_bearings().bearings.size(), 1U);
}

TEST(LandmarkBearings, OnlyLandmarksWithinTheCameraRangeAreSeen) {
  RobotProfile profile = exact_camera_profile();
  profile.camera_range_m = 2.0;
  Simulator sim(walled_world({{"near", 4.9, 5.0}, {"far", 1.0, 7.1}, {"edge", 3.0, 7.0}}), profile,
                1);
  EXPECT_EQ(names(sim.read_landmark_bearings()), (std::vector<std::string>{"near", "edge"}));
  // The R1 default (8 m) sees all of them.
  Simulator wide(walled_world({{"near", 4.9, 5.0}, {"far", 1.0, 7.1}, {"edge", 3.0, 7.0}}),
                 exact_camera_profile(), 1);
  EXPECT_EQ(wide.read_landmark_bearings().bearings.size(), 3U);
  // A world without landmarks gives an empty, stamped reading.
  Simulator none(walled_world({}), r1_profile(), 1);
  none.step(0.1);
  const msgs::LandmarkBearings empty = none.read_landmark_bearings();
  EXPECT_TRUE(empty.bearings.empty());
  EXPECT_DOUBLE_EQ(empty.stamp_s, 0.1);
}

TEST(LandmarkBearings, RejectsABadCameraProfile) {
  RobotProfile profile = r1_profile();
  profile.camera_range_m = -1.0;
  EXPECT_THROW(Simulator(walled_world({}), profile, 1), std::invalid_argument);
  profile = r1_profile();
  profile.bearing_sigma_rad = std::nan("");
  EXPECT_THROW(Simulator(walled_world({}), profile, 1), std::invalid_argument);
}

TEST(LandmarkBearings, NoiseHasTheProfileSigmaAndWraps) {
  RobotProfile profile = r1_profile();
  profile.wheel_speed_noise_fraction = 0.0;
  // Straight behind the robot, so the noise crosses +-pi and must be wrapped without bias.
  Simulator sim(walled_world({{"behind", 1.0, 5.0}}), profile, 11);
  constexpr int kReads = 4000;
  double sum_rad = 0.0;
  double sum_sq_rad2 = 0.0;
  int wrapped_negative = 0;
  for (int i = 0; i < kReads; ++i) {
    const msgs::LandmarkBearings seen = sim.read_landmark_bearings();
    ASSERT_EQ(seen.bearings.size(), 1U);
    const double bearing = seen.bearings[0].bearing_rad;
    ASSERT_GT(bearing, -kPi);
    ASSERT_LE(bearing, kPi);
    if (bearing < 0.0) ++wrapped_negative;
    const double error = geometry::wrap_angle(bearing - kPi);
    sum_rad += error;
    sum_sq_rad2 += error * error;
  }
  const double sigma = std::sqrt(sum_sq_rad2 / kReads);
  EXPECT_NEAR(sum_rad / kReads, 0.0, 4.0 * profile.bearing_sigma_rad / std::sqrt(kReads));
  EXPECT_NEAR(sigma, profile.bearing_sigma_rad, 0.05 * profile.bearing_sigma_rad);
  EXPECT_GT(wrapped_negative, kReads / 4);  // about half the readings land on the -pi side
  EXPECT_LT(wrapped_negative, 3 * kReads / 4);
}

std::vector<double> bearing_series(std::uint64_t seed, bool read_compass,
                                   std::vector<double>* compass = nullptr,
                                   std::vector<geometry::Pose2D>* poses = nullptr,
                                   bool read_bearings = true) {
  World world = load_world(resolve_world(testing::builtin_worlds_dir(), "office"));
  Simulator sim(std::move(world), r1_profile(), seed);
  std::vector<double> out;
  for (int i = 0; i < 500; ++i) {
    sim.set_command({0.6, 0.4 * std::sin(i * 0.01)});
    sim.step(0.02);
    if (poses != nullptr) poses->push_back(sim.true_pose());
    if (i % 5 != 0) continue;
    if (read_bearings) {
      for (const auto& bearing : sim.read_landmark_bearings().bearings) {
        out.push_back(bearing.bearing_rad);
      }
    }
    if (read_compass) {
      const double heading = sim.read_compass().heading_rad;
      if (compass != nullptr) compass->push_back(heading);
    }
  }
  return out;
}

TEST(LandmarkBearings, DeterministicPerSeedAndIndependentOfTheOtherStreams) {
  const std::vector<double> a = bearing_series(42, true);
  ASSERT_FALSE(a.empty());  // the office start sees the west corridor landmark
  EXPECT_EQ(a, bearing_series(42, true));
  EXPECT_NE(a, bearing_series(43, true));
  // Reading the compass does not change the bearings, nor the bearings the compass or the drive.
  EXPECT_EQ(a, bearing_series(42, false));
  std::vector<double> compass_with;
  std::vector<double> compass_without;
  std::vector<geometry::Pose2D> poses_with;
  std::vector<geometry::Pose2D> poses_without;
  bearing_series(42, true, &compass_with, &poses_with, true);
  bearing_series(42, true, &compass_without, &poses_without, false);
  EXPECT_EQ(compass_with, compass_without);
  EXPECT_EQ(poses_with, poses_without);
  // reset() reseeds the camera stream too.
  Simulator sim(walled_world({{"lm", 4.5, 6.0}}), r1_profile(), 5);
  const double first = sim.read_landmark_bearings().bearings.at(0).bearing_rad;
  sim.read_landmark_bearings();
  sim.reset(walled_world({}).start, 5);
  EXPECT_EQ(sim.read_landmark_bearings().bearings.at(0).bearing_rad, first);
}

}  // namespace
}  // namespace mobot::sim
