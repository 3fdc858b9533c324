#include "drivers/sim/simulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "drivers/sim/world_slice.h"
#include "tests/unit/drivers/sim/sim_test_support.h"

namespace mobot::sim {
namespace {

using testing::builtin_worlds_dir;
using testing::fill_cells;

constexpr double kPi = std::numbers::pi;
constexpr double kDt_s = 0.02;
constexpr std::size_t kCenterBeam = 180;

// R1 without random or systematic wheel error, so paths are exact lines.
RobotProfile ideal_profile() {
  RobotProfile profile = r1_profile();
  profile.left_wheel_scale = 1.0;
  profile.right_wheel_scale = 1.0;
  profile.track_scale = 1.0;
  profile.wheel_speed_noise_fraction = 0.0;
  return profile;
}

// 10 x 10 m at 0.05 m, closed, split by a wall at x 5.0..5.1 m.
World walled_world() {
  World world = testing::empty_world(200, 200, 0.05);
  testing::outer_walls(world.floor);
  fill_cells(world.floor, 100, 0, 101, 199);
  world.start = {3.0, 5.0, 0.0};
  return world;
}

World builtin(const std::string& name) {
  return load_world(resolve_world(builtin_worlds_dir(), name));
}

void drive(Simulator& sim, double linear_mps, double angular_radps, double duration_s) {
  sim.set_command({linear_mps, angular_radps});
  for (double t = 0.0; t < duration_s - 1e-9; t += kDt_s) sim.step(kDt_s);
}

TEST(RobotProfile, R1MatchesTheSpecification) {
  const RobotProfile profile = r1_profile();
  EXPECT_DOUBLE_EQ(profile.height_m, 1.2);
  EXPECT_DOUBLE_EQ(profile.laser_height_m, 0.4);
  EXPECT_EQ(profile.sonars_in_base.size(), 8U);
  EXPECT_DOUBLE_EQ(profile.max_linear_mps, 1.3);
  EXPECT_NE(profile.left_wheel_scale, profile.right_wheel_scale);  // something to calibrate
}

TEST(Simulator, StartsAtTheWorldStartAndRejectsBadSteps) {
  Simulator sim(walled_world(), ideal_profile(), 1);
  EXPECT_EQ(sim.true_pose(), (geometry::Pose2D{3.0, 5.0, 0.0}));
  EXPECT_EQ(sim.time_s(), 0.0);
  sim.step(0.5);
  EXPECT_DOUBLE_EQ(sim.time_s(), 0.5);
  EXPECT_EQ(sim.true_pose(), (geometry::Pose2D{3.0, 5.0, 0.0}));  // no command, no motion
  EXPECT_THROW(sim.step(-0.1), std::invalid_argument);
  EXPECT_THROW(sim.step(std::nan("")), std::invalid_argument);
}

TEST(Simulator, ClampsCommandsToTheProfileLimits) {
  Simulator sim(walled_world(), ideal_profile(), 1);
  sim.set_command({5.0, -10.0});
  EXPECT_EQ(sim.command(), (msgs::Twist{1.3, -2.0}));
  sim.set_command({std::nan(""), 1.0});
  EXPECT_EQ(sim.command(), (msgs::Twist{}));
}

TEST(Simulator, StraightRunEncodersMatchTheDistance) {
  Simulator sim(walled_world(), ideal_profile(), 1);
  drive(sim, 0.5, 0.0, 2.0);  // 1 m, stops short of the wall
  EXPECT_NEAR(sim.true_pose().x, 4.0, 1e-9);
  EXPECT_NEAR(sim.true_pose().y, 5.0, 1e-9);
  const msgs::WheelEncoders ticks = sim.read_encoders();
  const RobotProfile& profile = sim.profile();
  const double expected =
      1.0 / (2.0 * kPi * profile.wheel_radius_m) * static_cast<double>(profile.ticks_per_wheel_rev);
  EXPECT_NEAR(static_cast<double>(ticks.left_ticks), expected, 1.0);
  EXPECT_NEAR(static_cast<double>(ticks.right_ticks), expected, 1.0);
  EXPECT_DOUBLE_EQ(ticks.stamp_s, sim.time_s());
  drive(sim, -0.5, 0.0, 2.0);
  EXPECT_NEAR(static_cast<double>(sim.read_encoders().left_ticks), 0.0, 1.0);
}

TEST(Simulator, SystematicWheelErrorBendsAStraightRun) {
  // E1: about 3.86 % sideways error after 7 m that the encoders do not show.
  RobotProfile profile = r1_profile();
  profile.wheel_speed_noise_fraction = 0.0;
  World world = testing::empty_world(240, 80, 0.05, {-1.0, -2.0, 0.0});
  Simulator sim(std::move(world), profile, 1);
  drive(sim, 0.5, 0.0, 14.0);
  const msgs::WheelEncoders ticks = sim.read_encoders();
  EXPECT_EQ(ticks.left_ticks, ticks.right_ticks);
  const double sideways_fraction = std::abs(sim.true_pose().y) / sim.true_pose().x;
  EXPECT_GT(sideways_fraction, 0.025);
  EXPECT_LT(sideways_fraction, 0.055);
  EXPECT_GT(sim.true_pose().y, 0.0);  // the larger right wheel turns the robot left
}

TEST(Simulator, TurnsAtTheCommandedRateWithAnIdealProfile) {
  Simulator sim(walled_world(), ideal_profile(), 1);
  drive(sim, 0.0, 1.0, kPi / 2);
  EXPECT_NEAR(sim.true_pose().theta, kPi / 2, 0.021);  // one step of quantisation
  EXPECT_NEAR(sim.true_pose().x, 3.0, 1e-9);
}

TEST(Simulator, DrivingIntoAWallStopsAndQueuesOneCollision) {
  Simulator sim(walled_world(), ideal_profile(), 1);
  drive(sim, 1.0, 0.0, 3.0);
  // The 0.6 m body stops with its front on the wall face at x = 5.0.
  EXPECT_NEAR(sim.true_pose().x, 4.7, 1e-3);
  EXPECT_LE(sim.true_pose().x, 4.7);
  EXPECT_FALSE(sim.pose_collides(sim.true_pose()));
  EXPECT_EQ(sim.collision_count(), 1);
  EXPECT_EQ(sim.command(), (msgs::Twist{}));
  const auto collisions = sim.take_collisions();
  ASSERT_EQ(collisions.size(), 1U);
  EXPECT_EQ(collisions[0].with, "wall");
  EXPECT_NEAR(collisions[0].pose.x, 4.7, 1e-3);
  EXPECT_TRUE(sim.take_collisions().empty());

  // Pushing on against the wall is blocked but is the same collision.
  drive(sim, 1.0, 0.0, 1.0);
  EXPECT_NEAR(sim.true_pose().x, 4.7, 1e-3);
  EXPECT_EQ(sim.collision_count(), 1);
  // Backing off and driving in again is a new one.
  drive(sim, -0.5, 0.0, 1.0);
  EXPECT_NEAR(sim.true_pose().x, 4.2, 2e-3);
  drive(sim, 0.5, 0.0, 2.0);
  EXPECT_EQ(sim.collision_count(), 2);
  EXPECT_EQ(sim.take_collisions().size(), 1U);
}

TEST(Simulator, EncodersStopWithTheRobot) {
  Simulator sim(walled_world(), ideal_profile(), 1);
  drive(sim, 1.0, 0.0, 3.0);
  const auto at_wall = sim.read_encoders();
  drive(sim, 1.0, 0.0, 1.0);
  EXPECT_EQ(sim.read_encoders().left_ticks, at_wall.left_ticks);
  const double travelled_m = static_cast<double>(at_wall.left_ticks) /
                             static_cast<double>(sim.profile().ticks_per_wheel_rev) * 2.0 * kPi *
                             sim.profile().wheel_radius_m;
  EXPECT_NEAR(travelled_m, 1.7, 2e-3);
}

TEST(Simulator, GateAsLowBeamBlocksTheRobotGateBDoesNot) {
  Simulator through_a(builtin("g2_lobby"), ideal_profile(), 1);
  drive(through_a, 0.5, 0.0, 14.0);
  const auto collisions = through_a.take_collisions();
  ASSERT_EQ(collisions.size(), 1U);
  EXPECT_EQ(collisions[0].with, "gate_a_beam");
  EXPECT_NEAR(through_a.true_pose().y, 3.0 - 0.3, 1e-3);

  Simulator through_b(builtin("g2_lobby"), ideal_profile(), 1);
  through_b.reset({-2.2, 0.0, kPi / 2}, 1);
  drive(through_b, 0.5, 0.0, 12.0);
  EXPECT_EQ(through_b.collision_count(), 0);
  EXPECT_NEAR(through_b.true_pose().y, 6.0, 1e-6);
}

TEST(Simulator, TheLaserSeesGateAOpen) {
  Simulator sim(builtin("g2_lobby"), ideal_profile(), 1);
  const msgs::LaserScan scan = sim.read_laser();
  // Straight ahead through gate A to the north wall's face at y = 9.8; the laser is at y = 0.2.
  EXPECT_NEAR(scan.ranges_m[kCenterBeam], 9.6, 0.06);
}

TEST(Simulator, TablesCollideButTheLaserPassesUnderThem) {
  Simulator sim(builtin("office"), ideal_profile(), 1);
  EXPECT_TRUE(sim.pose_collides({15.8, 11.4, 0.0}));
  sim.reset({15.8, 9.5, kPi / 2}, 1);
  // Under table_1 (y 11.0..11.8) to the north wall at y = 14.8.
  EXPECT_NEAR(sim.read_laser().ranges_m[kCenterBeam], 14.8 - 9.7, 0.06);
  drive(sim, 0.5, 0.0, 4.0);
  const auto collisions = sim.take_collisions();
  ASSERT_EQ(collisions.size(), 1U);
  EXPECT_EQ(collisions[0].with, "table_1");
  EXPECT_NEAR(sim.true_pose().y, 11.0 - 0.3, 1e-3);
}

TEST(Simulator, TheLaserSeesTheCabinet) {
  Simulator sim(builtin("office"), ideal_profile(), 1);
  sim.reset({1.0, 12.0, kPi / 2}, 1);
  EXPECT_NEAR(sim.read_laser().ranges_m[kCenterBeam], 14.2 - 12.2, 0.06);
}

TEST(Simulator, LaserScanLayoutAndNoise) {
  Simulator sim(walled_world(), ideal_profile(), 3);
  const msgs::LaserScan scan = sim.read_laser();
  ASSERT_EQ(scan.ranges_m.size(), 361U);
  EXPECT_FLOAT_EQ(scan.angle_min_rad, static_cast<float>(-kPi / 2));
  EXPECT_FLOAT_EQ(scan.angle_increment_rad, static_cast<float>(kPi / 360));
  EXPECT_FLOAT_EQ(scan.range_min_m, 0.4F);
  EXPECT_FLOAT_EQ(scan.range_max_m, 80.0F);
  EXPECT_EQ(scan.sensor_in_base, (geometry::Pose2D{0.2, 0.0, 0.0}));
  // A closed world: every beam returns.
  for (const float range : scan.ranges_m) EXPECT_LE(range, scan.range_max_m);
  // The wall at x = 5.0 is 1.8 m ahead of the laser at x = 3.2; the right-most beam (-90 deg)
  // meets the south wall's face at y = 0.05.
  double sum_m = 0.0;
  double sum_sq_m2 = 0.0;
  constexpr int kScans = 400;
  for (int i = 0; i < kScans; ++i) {
    const double range = sim.read_laser().ranges_m[kCenterBeam];
    sum_m += range;
    sum_sq_m2 += range * range;
  }
  const double mean_m = sum_m / kScans;
  const double sigma_m = std::sqrt(sum_sq_m2 / kScans - mean_m * mean_m);
  EXPECT_NEAR(mean_m, 1.8, 0.003);
  EXPECT_NEAR(sigma_m, 0.01, 0.002);
  EXPECT_NEAR(scan.ranges_m.front(), 5.0 - 0.05, 0.05);
}

TEST(Simulator, NoReturnReadsBeyondRangeMax) {
  World open = testing::empty_world(40, 40, 0.05);
  open.start = {1.0, 1.0, 0.3};
  Simulator sim(std::move(open), ideal_profile(), 1);
  for (const float range : sim.read_laser().ranges_m) EXPECT_FLOAT_EQ(range, 81.0F);
}

TEST(Simulator, SonarSeesAWallInsideItsCone) {
  Simulator sim(walled_world(), ideal_profile(), 5);
  const msgs::SonarRing ring = sim.read_sonar();
  ASSERT_EQ(ring.readings.size(), 8U);
  // Sonar 1 at (0.30, 0.07) looking 15 deg left: its cone spans 3.75..26.25 deg, so the nearest
  // echo is 1.7 m / cos(3.75 deg) = 1.704 m away.
  const msgs::RangeReading& front = ring.readings[1];
  EXPECT_NEAR(front.range_m, 1.704, 0.1);
  EXPECT_DOUBLE_EQ(front.cone_rad, 22.5 * kPi / 180.0);
  EXPECT_DOUBLE_EQ(front.range_max_m, 4.0);
  EXPECT_EQ(front.sensor_in_base, sim.profile().sonars_in_base[1]);
  // The side sonars look at walls 4.65 m away: beyond the SRF05's 4 m.
  EXPECT_DOUBLE_EQ(ring.readings[4].range_m, 4.0);
  EXPECT_DOUBLE_EQ(ring.readings[6].range_m, 4.0);
  // Turned to face the south wall from 0.5 m, the side sonar sees it.
  sim.reset({3.0, 0.85, 0.0}, 5);
  EXPECT_NEAR(sim.read_sonar().readings[6].range_m, 0.85 - 0.3 - 0.05, 0.05);
}

TEST(Simulator, CompassNoiseHasTheProfileSigma) {
  Simulator sim(walled_world(), ideal_profile(), 9);
  sim.reset({3.0, 5.0, kPi}, 9);  // wrapping at +-pi must not bias the error
  constexpr int kReads = 4000;
  double sum_rad = 0.0;
  double sum_sq_rad2 = 0.0;
  for (int i = 0; i < kReads; ++i) {
    const double heading = sim.read_compass().heading_rad;
    ASSERT_GT(heading, -kPi);
    ASSERT_LE(heading, kPi);
    const double error = geometry::wrap_angle(heading - kPi);
    sum_rad += error;
    sum_sq_rad2 += error * error;
  }
  const double sigma = std::sqrt(sum_sq_rad2 / kReads);
  EXPECT_NEAR(sum_rad / kReads, 0.0, 4.0 * sim.profile().compass_sigma_rad / std::sqrt(kReads));
  EXPECT_NEAR(sigma, sim.profile().compass_sigma_rad, 0.1 * sim.profile().compass_sigma_rad);
}

TEST(Simulator, ObstaclesCanBeAddedAndRemoved) {
  Simulator sim(walled_world(), ideal_profile(), 1);
  const int post = sim.add_obstacle(4.5, 5.0, 0.2, 1.0);
  const int stool = sim.add_obstacle(3.0, 7.0, 0.2, 0.3);  // lower than the laser
  EXPECT_EQ(post, 1);
  EXPECT_EQ(stool, 2);
  EXPECT_EQ(sim.obstacles().size(), 2U);
  EXPECT_NEAR(sim.read_laser().ranges_m[kCenterBeam], 4.3 - 3.2, 0.05);
  // The stool, 2 m to the left, is under the laser plane: the left beam reaches the outer wall.
  EXPECT_NEAR(sim.read_laser().ranges_m.back(), 9.95 - 5.0, 0.05);
  EXPECT_TRUE(sim.pose_collides({3.0, 7.3, 0.0}));

  drive(sim, 0.5, 0.0, 3.0);
  const auto collisions = sim.take_collisions();
  ASSERT_EQ(collisions.size(), 1U);
  EXPECT_EQ(collisions[0].with, "obstacle 1");
  EXPECT_NEAR(sim.true_pose().x, 4.3 - 0.3, 1e-3);

  EXPECT_TRUE(sim.remove_obstacle(post));
  EXPECT_FALSE(sim.remove_obstacle(post));
  EXPECT_FALSE(sim.remove_obstacle(42));
  EXPECT_NEAR(sim.read_laser().ranges_m[kCenterBeam], 5.0 - 4.2, 0.05);
  EXPECT_THROW(sim.add_obstacle(1.0, 1.0, 0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(sim.add_obstacle(1.0, std::nan(""), 0.1, 1.0), std::invalid_argument);
  EXPECT_EQ(sim.add_obstacle(8.0, 8.0, 0.1, 1.0), 3);
}

// Every beam against the slow answer: the static caster plus every obstacle tried on every beam.
void expect_scan_matches_brute_force(RobotProfile profile, std::uint64_t seed) {
  profile.laser_range_sigma_m = 0.0;
  Simulator sim(walled_world(), profile, seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> x_of(0.3, 9.7);
  std::uniform_real_distribution<double> radius_of(0.05, 0.5);
  for (int i = 0; i < 25; ++i) sim.add_obstacle(x_of(rng), x_of(rng), radius_of(rng), 1.0);
  sim.reset({3.0, 5.0, 2.5}, seed);  // reset clears them: add them again around the new pose
  for (int i = 0; i < 25; ++i) sim.add_obstacle(x_of(rng), x_of(rng), radius_of(rng), 1.0);
  const RayCaster walls(slice_at_height(sim.world(), profile.laser_height_m));
  const msgs::LaserScan scan = sim.read_laser();
  const geometry::Pose2D laser = geometry::compose(sim.true_pose(), profile.laser_in_base);
  int blocked_by_obstacles = 0;
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double angle =
        laser.theta - profile.laser_fov_rad / 2 + static_cast<double>(i) * profile.laser_step_rad;
    double expected = walls.cast({laser.x, laser.y}, angle, profile.laser_range_max_m)
                          .value_or(profile.laser_range_max_m + 1.0);
    for (const Obstacle& obstacle : sim.obstacles()) {
      const auto hit = cast_to_circle({laser.x, laser.y}, angle, {obstacle.x_m, obstacle.y_m},
                                      obstacle.radius_m);
      if (hit && *hit < expected) {
        expected = *hit;
        ++blocked_by_obstacles;
      }
    }
    ASSERT_NEAR(scan.ranges_m[i], expected, 1e-4) << "beam " << i;
  }
  EXPECT_GT(blocked_by_obstacles, 20);
}

TEST(Simulator, LaserSeesObstaclesOnExactlyTheBeamsThatMeetThem) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed)
    expect_scan_matches_brute_force(ideal_profile(), seed);
  RobotProfile full_circle = ideal_profile();
  full_circle.laser_fov_rad = 2 * kPi;
  full_circle.laser_step_rad = kPi / 180;
  for (std::uint64_t seed = 1; seed <= 5; ++seed)
    expect_scan_matches_brute_force(full_circle, seed);
}

TEST(Simulator, AnObstacleDroppedOnTheRobotDoesNotTrapIt) {
  Simulator sim(walled_world(), ideal_profile(), 1);
  sim.add_obstacle(3.1, 5.0, 0.1, 1.0);
  EXPECT_TRUE(sim.pose_collides(sim.true_pose()));
  drive(sim, -0.5, 0.0, 2.0);
  EXPECT_NEAR(sim.true_pose().x, 2.0, 1e-6);
  EXPECT_EQ(sim.collision_count(), 0);
}

TEST(Simulator, ResetClearsTheRun) {
  Simulator sim(walled_world(), ideal_profile(), 1);
  sim.add_obstacle(4.0, 5.0, 0.2, 1.0);
  drive(sim, 1.0, 0.0, 2.0);
  ASSERT_EQ(sim.collision_count(), 1);
  sim.reset({2.0, 2.0, 1.0}, 2);
  EXPECT_EQ(sim.true_pose(), (geometry::Pose2D{2.0, 2.0, 1.0}));
  EXPECT_EQ(sim.time_s(), 0.0);
  EXPECT_EQ(sim.collision_count(), 0);
  EXPECT_TRUE(sim.take_collisions().empty());
  EXPECT_TRUE(sim.obstacles().empty());
  EXPECT_EQ(sim.read_encoders().left_ticks, 0);
  EXPECT_EQ(sim.command(), (msgs::Twist{}));
  EXPECT_EQ(sim.add_obstacle(8.0, 8.0, 0.1, 1.0), 1);
}

TEST(Simulator, PoseCollidesOutsideTheFloorPlan) {
  const Simulator sim(walled_world(), ideal_profile(), 1);
  EXPECT_FALSE(sim.pose_collides({3.0, 5.0, 0.7}));
  EXPECT_TRUE(sim.pose_collides({4.8, 5.0, 0.0}));
  EXPECT_TRUE(sim.pose_collides({-3.0, 5.0, 0.0}));
  EXPECT_TRUE(sim.pose_collides({0.3, 5.0, kPi / 4}));  // a corner reaches the outer wall
}

// A drive with turns, reading every sensor now and then.
struct Recording {
  std::vector<geometry::Pose2D> poses;
  std::vector<std::vector<float>> scans;
  std::vector<double> sonar_m;
  std::vector<double> compass_rad;
  std::vector<std::int64_t> ticks;
};

Recording record(std::uint64_t seed, bool read_sensors = true) {
  Simulator sim(builtin("office"), r1_profile(), seed);
  Recording out;
  for (int i = 0; i < 600; ++i) {
    sim.set_command({0.6, 0.5 * std::sin(i * 0.01)});
    sim.step(kDt_s);
    out.poses.push_back(sim.true_pose());
    if (read_sensors && i % 10 == 0) {
      out.scans.push_back(sim.read_laser().ranges_m);
      for (const auto& reading : sim.read_sonar().readings) out.sonar_m.push_back(reading.range_m);
      out.compass_rad.push_back(sim.read_compass().heading_rad);
      out.ticks.push_back(sim.read_encoders().left_ticks);
    }
  }
  return out;
}

TEST(Simulator, SameSeedSameRunDifferentSeedDifferentRun) {
  const Recording a = record(42);
  const Recording b = record(42);
  const Recording c = record(43);
  EXPECT_EQ(a.poses, b.poses);
  EXPECT_EQ(a.scans, b.scans);
  EXPECT_EQ(a.sonar_m, b.sonar_m);
  EXPECT_EQ(a.compass_rad, b.compass_rad);
  EXPECT_EQ(a.ticks, b.ticks);
  EXPECT_NE(a.poses, c.poses);
  EXPECT_NE(a.scans, c.scans);
  EXPECT_NE(a.compass_rad, c.compass_rad);
}

TEST(Simulator, ReadingSensorsDoesNotChangeTheDrive) {
  EXPECT_EQ(record(42, true).poses, record(42, false).poses);
}

}  // namespace
}  // namespace mobot::sim
