// The Dashgo D1 in the simulator (docs/algorithms.md R2): its profile, each sensor at its own
// height, the IR ring's ADC counts, and odometry that drifts like a real base's.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <numbers>

#include "core/control/velocity_smoother.h"
#include "core/estimation/wheel_odometry.h"
#include "core/safety/sharp_ir_curve.h"
#include "drivers/sim/robot_profile.h"
#include "drivers/sim/sim_backend.h"
#include "drivers/sim/simulator.h"
#include "tests/unit/drivers/sim/sim_test_support.h"

namespace mobot::sim {
namespace {

using testing::builtin_worlds_dir;

constexpr double kPi = std::numbers::pi;
constexpr double kDt_s = 0.02;
constexpr std::size_t kIrAhead = 3;  // the ring's sensor at 0 deg

World builtin(const std::string& name) {
  return load_world(resolve_world(builtin_worlds_dir(), name));
}

// The Dashgo without random errors: sensors read the truth, the drive goes where it is told.
RobotProfile exact_dashgo() {
  RobotProfile profile = dashgo_d1_profile();
  set_odometry_errors(profile, {});
  profile.traction_accel_mps2 = 0.0;
  profile.wheel_speed_noise_fraction = 0.0;
  profile.laser_range_sigma_m = 0.0;
  profile.laser_range_sigma_fraction = 0.0;
  profile.sonar_noise_fraction = 0.0;
  profile.ir_adc.noise_v = 0.0;
  profile.ir_adc.gain_sigma = 0.0;
  profile.ir_adc.spike_probability = 0.0;
  return profile;
}

void drive(Simulator& sim, double linear_mps, double angular_radps, double duration_s) {
  sim.set_command({linear_mps, angular_radps});
  for (double t = 0.0; t < duration_s - 1e-9; t += kDt_s) sim.step(kDt_s);
}

// The beam of a 360 deg scan nearest a bearing in the base frame.
float beam_at(const msgs::LaserScan& scan, double bearing_rad) {
  const double offset = geometry::wrap_angle(bearing_rad - scan.angle_min_rad);
  const double index = std::fmod(offset + 2 * kPi, 2 * kPi) / scan.angle_increment_rad;
  return scan.ranges_m[static_cast<std::size_t>(std::lround(index)) % scan.ranges_m.size()];
}

double ir_range_m(const std::vector<int>& counts, std::size_t sensor) {
  return safety::SharpIrCurve(dashgo_d1_profile().ir_adc.curve).ring_range_m(counts[sensor]);
}

TEST(DashgoD1, MatchesR2) {
  const RobotProfile p = dashgo_d1_profile();
  EXPECT_DOUBLE_EQ(2 * p.wheel_radius_m, 0.128);
  EXPECT_DOUBLE_EQ(p.track_m, 0.3559);
  EXPECT_EQ(p.ticks_per_wheel_rev, 1200);
  EXPECT_DOUBLE_EQ(p.max_linear_mps, 0.5);
  EXPECT_DOUBLE_EQ(p.max_angular_radps, 0.7);
  EXPECT_DOUBLE_EQ(p.footprint_length_m, 0.40);
  EXPECT_DOUBLE_EQ(p.footprint_width_m, 0.40);
  EXPECT_GE(p.height_m, 0.7) << "the body must carry the IR ring";
  EXPECT_DOUBLE_EQ(p.laser_height_m, 0.2);
  EXPECT_DOUBLE_EQ(p.laser_fov_rad, 2 * kPi);
  EXPECT_DOUBLE_EQ(p.laser_range_min_m, 0.10);
  EXPECT_DOUBLE_EQ(p.laser_range_max_m, 16.0);
  ASSERT_EQ(p.sonars_in_base.size(), 4U);
  EXPECT_EQ(p.sonars_in_base[0], (geometry::Pose2D{0.18, 0.10, kPi / 6}));
  EXPECT_EQ(p.sonars_in_base[3], (geometry::Pose2D{-0.20, 0.0, kPi}));
  EXPECT_DOUBLE_EQ(p.sonar_cone_rad, 0.3);
  EXPECT_DOUBLE_EQ(p.sonar_range_max_m, 0.8);
  ASSERT_EQ(p.ir_sensors_in_base.size(), 10U);
  for (const auto& mount : p.ir_sensors_in_base) {
    EXPECT_NEAR(std::hypot(mount.x, mount.y), 0.145, 1e-12);
    EXPECT_NEAR(std::atan2(mount.y, mount.x), mount.theta, 1e-12) << "looks out along its radius";
  }
  EXPECT_NEAR(p.ir_sensors_in_base[0].theta, -kPi / 4, 1e-12);
  EXPECT_NEAR(p.ir_sensors_in_base[9].theta, -155 * kPi / 180, 1e-12);  // 205 deg
  EXPECT_DOUBLE_EQ(p.ir_height_m, 0.7);
  EXPECT_DOUBLE_EQ(p.ir_rate_hz, 20.0);
  EXPECT_FALSE(p.has_compass);
  EXPECT_FALSE(p.has_tilt_laser);
  const OdometryErrors errors = odometry_errors_of(p);
  EXPECT_NEAR(errors.scale_error, 0.01, 1e-12);
  EXPECT_NEAR(errors.heading_drift_rad_per_m, 0.004, 1e-12);
  EXPECT_DOUBLE_EQ(errors.step_noise_fraction, 0.03);
}

TEST(RobotProfiles, OneTableEntryPerRobot) {
  ASSERT_EQ(robot_profiles().size(), 5U);
  EXPECT_EQ(robot_profiles()[0].name, "r1");
  EXPECT_EQ(robot_profiles()[1].name, "dashgo_d1");
  EXPECT_EQ(robot_profiles()[2].name, "tricycle_t1");
  EXPECT_EQ(robot_profiles()[3].name, "tricycle_t2");
  EXPECT_EQ(robot_profiles()[4].name, "camera_robot");
  EXPECT_TRUE(profile_named("tricycle_t1")->steering.has_value());
  EXPECT_FALSE(profile_named("r1")->steering.has_value());
  EXPECT_TRUE(profile_named("camera_robot")->pan_tilt_camera.has_value());
  ASSERT_TRUE(profile_named("dashgo_d1"));
  EXPECT_DOUBLE_EQ(profile_named("dashgo_d1")->track_m, 0.3559);
  EXPECT_DOUBLE_EQ(profile_named("r1")->track_m, r1_profile().track_m);
  EXPECT_FALSE(profile_named("R1"));
  EXPECT_FALSE(profile_named(""));
}

TEST(RobotProfiles, OdometryErrorsRoundTripThroughTheWheelScales) {
  RobotProfile p = dashgo_d1_profile();
  set_odometry_errors(p, {-0.02, -0.01, 0.05});
  EXPECT_LT(p.right_wheel_scale, p.left_wheel_scale) << "a negative drift turns right";
  EXPECT_NEAR((p.left_wheel_scale + p.right_wheel_scale) / 2, 1.0 / 0.98, 1e-12);
  const OdometryErrors back = odometry_errors_of(p);
  EXPECT_NEAR(back.scale_error, -0.02, 1e-12);
  EXPECT_NEAR(back.heading_drift_rad_per_m, -0.01, 1e-12);
  EXPECT_DOUBLE_EQ(back.step_noise_fraction, 0.05);
  // R1's scales read as errors too (its 0.66 % radius difference on a 0.6 m track).
  const OdometryErrors r1 = odometry_errors_of(r1_profile());
  EXPECT_NEAR(r1.scale_error, 0.0, 1e-12);
  EXPECT_NEAR(r1.heading_drift_rad_per_m, 0.0066 / (0.6 * 1.01), 1e-12);
  EXPECT_THROW(set_odometry_errors(p, {-1.0, 0.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(set_odometry_errors(p, {0.0, std::nan(""), 0.0}), std::invalid_argument);
  EXPECT_THROW(set_odometry_errors(p, {0.0, 0.0, -0.1}), std::invalid_argument);
}

TEST(DashgoD1, TheLidarSeesAllAroundAtItsHeight) {
  World world = testing::empty_world(200, 200, 0.05);
  testing::outer_walls(world.floor);
  world.start = {5.0, 5.0, 0.0};
  // A low box (0..0.15 m): under the lidar's plane, in the sonars'.
  world.boxes.push_back({6.0, 4.0, 6.5, 6.0, 0.0, 0.15, "low_box"});
  Simulator sim(std::move(world), exact_dashgo(), 1);
  const msgs::LaserScan scan = sim.read_laser();
  ASSERT_EQ(scan.ranges_m.size(), 720U) << "360 deg at 0.5 deg, no beam twice";
  EXPECT_FLOAT_EQ(scan.angle_min_rad, static_cast<float>(-kPi));
  EXPECT_FLOAT_EQ(scan.range_max_m, 16.0F);
  EXPECT_FLOAT_EQ(scan.range_min_m, 0.10F);
  // Walls' faces at x = 0.05 and 9.95, y likewise; the laser is at the base centre.
  EXPECT_NEAR(beam_at(scan, 0.0), 4.95, 1e-3) << "over the low box";
  EXPECT_NEAR(beam_at(scan, kPi), 4.95, 1e-3);
  EXPECT_NEAR(beam_at(scan, kPi / 2), 4.95, 1e-3);
  EXPECT_NEAR(beam_at(scan, -kPi / 2), 4.95, 1e-3);
  // From 0.5 m the front sonar, 0.1 m above the floor, sees the low box.
  sim.reset({5.3, 5.0, 0.0}, 1);
  const msgs::SonarRing sonar = sim.read_sonar();
  ASSERT_EQ(sonar.readings.size(), 4U);
  EXPECT_NEAR(sonar.readings[1].range_m, 6.0 - 5.5, 1e-3);
  EXPECT_NEAR(beam_at(sim.read_laser(), 0.0), 9.95 - 5.3, 1e-3) << "the lidar does not";
}

TEST(DashgoD1, NoReturnBeyondSixteenMetresAndTheNoiseGrowsWithRange) {
  World open = testing::empty_world(40, 40, 0.05);
  open.start = {1.0, 1.0, 0.3};
  RobotProfile profile = dashgo_d1_profile();
  Simulator empty(std::move(open), profile, 1);
  for (const float range : empty.read_laser().ranges_m) EXPECT_FLOAT_EQ(range, 17.0F);

  // A wall 10 m ahead: sigma = max(1 cm, 0.5 % of 10 m) = 5 cm.
  World long_room = testing::empty_world(240, 40, 0.05);
  testing::outer_walls(long_room.floor);
  long_room.start = {1.0, 1.0, 0.0};
  Simulator sim(std::move(long_room), profile, 2);
  const double expected_m = 11.95 - 1.0;
  double sum = 0.0;
  double sum_sq = 0.0;
  constexpr int kScans = 400;
  for (int i = 0; i < kScans; ++i) {
    const double range = beam_at(sim.read_laser(), 0.0);
    sum += range;
    sum_sq += range * range;
  }
  const double mean = sum / kScans;
  EXPECT_NEAR(mean, expected_m, 0.01);
  EXPECT_NEAR(std::sqrt(sum_sq / kScans - mean * mean), 0.005 * expected_m, 0.008);
}

TEST(DashgoD1, TheIrOnlyTableIsSeenOnlyByTheIrRingAndStillHitsTheBody) {
  // Facing south toward table_ir (x 0.6..1.8, y 3.4..4.2, top 0.60..0.75 m) from 0.8 m.
  Simulator sim(builtin("office"), exact_dashgo(), 1);
  const geometry::Pose2D facing_table{1.2, 5.0, -kPi / 2};
  sim.reset(facing_table, 1);
  // The ring's front sensor sits 0.145 m ahead of the centre: 0.655 m to the table's edge.
  EXPECT_NEAR(ir_range_m(sim.read_ir_adc(), kIrAhead), 0.655, 0.01);
  // The lidar at 0.2 m runs under it to the south wall's face at y = 0.2.
  EXPECT_NEAR(beam_at(sim.read_laser(), 0.0), 5.0 - 0.2, 1e-3);
  // The sonars at 0.1 m see nothing within their 0.8 m.
  EXPECT_DOUBLE_EQ(sim.read_sonar().readings[1].range_m, 0.8);
  // Nor is the table on the surveyed map.
  const mapping::OccupancyGrid map = surveyed_map(sim.world(), sim.profile().height_m);
  EXPECT_FALSE(map.is_occupied(*map.cell_at({1.2, 3.8})));
  EXPECT_TRUE(map.is_occupied(*map.cell_at({3.8, 2.9}))) << "table_2 is drawn on it";
  // Driving on, the 0.75 m body hits its top.
  drive(sim, 0.3, 0.0, 4.0);
  const auto collisions = sim.take_collisions();
  ASSERT_EQ(collisions.size(), 1U);
  EXPECT_EQ(collisions[0].with, "table_ir");
  EXPECT_NEAR(sim.true_pose().y, 4.2 + 0.2, 1e-3);
  // Touching it the front sensor is 5.5 cm off: too near, reported at the window's edge.
  EXPECT_DOUBLE_EQ(ir_range_m(sim.read_ir_adc(), kIrAhead), 0.10);
}

TEST(DashgoD1, EachSensorSeesDroppedObstaclesAsTallAsItsHeight) {
  World world = testing::empty_world(200, 200, 0.05);
  testing::outer_walls(world.floor);
  world.start = {5.0, 5.0, 0.0};
  Simulator sim(std::move(world), exact_dashgo(), 1);
  // 0.15 m tall, 0.5 m ahead: the sonars see it, the lidar (0.2 m) and IR ring (0.7 m) do not.
  const int low = sim.add_obstacle(5.6, 5.0, 0.1, 0.15);
  EXPECT_NEAR(sim.read_sonar().readings[1].range_m, 0.5 - 0.2, 0.01);
  EXPECT_NEAR(beam_at(sim.read_laser(), 0.0), 4.95, 1e-3);
  EXPECT_EQ(ir_range_m(sim.read_ir_adc(), kIrAhead), 0.8);
  sim.remove_obstacle(low);
  // 1 m tall: all three.
  sim.add_obstacle(5.6, 5.0, 0.1, 1.0);
  EXPECT_NEAR(sim.read_sonar().readings[1].range_m, 0.3, 0.01);
  EXPECT_NEAR(beam_at(sim.read_laser(), 0.0), 0.5, 1e-3);
  EXPECT_NEAR(ir_range_m(sim.read_ir_adc(), kIrAhead), 0.5 - 0.145, 0.01);
}

TEST(DashgoD1, TheIrCountsCarryTheSensorsNoiseAndGainAndRepeatForASeed) {
  World world = testing::empty_world(200, 200, 0.05);
  testing::outer_walls(world.floor);
  world.start = {9.5, 5.0, 0.0};  // 0.45 m from the east wall's face: 0.305 m for the sensor
  const RobotProfile profile = dashgo_d1_profile();
  Simulator a(world, profile, 7);
  Simulator b(world, profile, 7);
  Simulator c(world, profile, 8);
  std::vector<double> ranges;
  bool differs = false;
  for (int i = 0; i < 400; ++i) {
    const std::vector<int> counts = a.read_ir_adc();
    ASSERT_EQ(counts.size(), 10U);
    ASSERT_EQ(counts, b.read_ir_adc());
    differs = differs || counts != c.read_ir_adc();
    for (const int count : counts) {
      ASSERT_GE(count, 0);
      ASSERT_LE(count, 1023);
    }
    ranges.push_back(ir_range_m(counts, kIrAhead));
  }
  EXPECT_TRUE(differs);
  double mean = 0.0;
  for (const double r : ranges) mean += r / ranges.size();
  double var = 0.0;
  for (const double r : ranges) var += (r - mean) * (r - mean) / ranges.size();
  // The unit's gain (3 %) moves the mean by about 3.6 %; the reading noise is about 1 cm at
  // 30 cm, more with the odd spike.
  EXPECT_NEAR(mean, 0.305, 0.04);
  EXPECT_GT(std::sqrt(var), 0.005);
  EXPECT_LT(std::sqrt(var), 0.04);
}

TEST(DashgoD1, BackendGivesTheDashgosDriversAndConvertsTheIrCounts) {
  drivers::BackendOptions options;
  options.profile = "dashgo_d1";
  options.world = "office";
  options.worlds_dir = builtin_worlds_dir();
  options.laser_rate_hz = 7.0;
  auto backend = make_sim_backend(options);
  drivers::DriverSet& drivers = backend->drivers();
  ASSERT_TRUE(drivers.ir);
  EXPECT_EQ(drivers.ir->name(), "ir");
  EXPECT_DOUBLE_EQ(drivers.ir->nominal_rate_hz(), 20.0);
  EXPECT_TRUE(drivers.laser);
  EXPECT_TRUE(drivers.sonar);
  EXPECT_FALSE(drivers.compass) << "the Dashgo has none";
  EXPECT_FALSE(drivers.bearings);
  EXPECT_FALSE(drivers.tilt);
  EXPECT_DOUBLE_EQ(backend->geometry().track_m, 0.3559);

  backend->reset(nullptr, geometry::Pose2D{1.2, 5.0, -kPi / 2}, std::nullopt);
  const auto ring = drivers.ir->poll(0.0);
  ASSERT_TRUE(ring);
  ASSERT_EQ(ring->readings.size(), 10U);
  EXPECT_NEAR(ring->readings[kIrAhead].range_m, 0.655, 0.06) << "table_ir";
  EXPECT_DOUBLE_EQ(ring->readings[kIrAhead].range_min_m, 0.10);
  EXPECT_DOUBLE_EQ(ring->readings[kIrAhead].range_max_m, 0.80);
  EXPECT_EQ(ring->readings[kIrAhead].sensor_in_base,
            backend->profile().ir_sensors_in_base[kIrAhead]);
  EXPECT_FALSE(drivers.ir->poll(0.02)) << "20 Hz";
  EXPECT_TRUE(drivers.ir->poll(0.05));

  // R1 keeps its devices and has no IR ring.
  options.profile = "r1";
  auto r1 = make_sim_backend(options);
  EXPECT_FALSE(r1->drivers().ir);
  EXPECT_TRUE(r1->drivers().compass);
  EXPECT_TRUE(r1->drivers().tilt);

  options.profile = "dashgo";
  EXPECT_THROW(make_sim_backend(options), drivers::BackendError);
}

TEST(DashgoD1, TheConfigOverridesTheOdometryErrors) {
  drivers::BackendOptions options;
  options.profile = "dashgo_d1";
  options.worlds_dir = builtin_worlds_dir();
  options.odometry_errors.heading_drift_rad_per_m = 0.0;
  options.odometry_errors.step_noise_fraction = 0.01;
  const OdometryErrors errors = odometry_errors_of(make_sim_backend(options)->profile());
  EXPECT_NEAR(errors.scale_error, 0.01, 1e-12) << "kept from the profile";
  EXPECT_NEAR(errors.heading_drift_rad_per_m, 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(errors.step_noise_fraction, 0.01);
  options.odometry_errors.scale_error = -1.5;
  EXPECT_THROW(make_sim_backend(options), drivers::BackendError);
}

TEST(DashgoD1, AHardStopSlidesOnWhileTheEncodersStop) {
  World world = testing::empty_world(200, 200, 0.05);
  world.start = {2.0, 5.0, 0.0};
  RobotProfile profile = exact_dashgo();
  profile.traction_accel_mps2 = 3.0;
  Simulator sim(std::move(world), profile, 1);
  drive(sim, 0.5, 0.0, 4.0);  // the start slips: 0.5 m/s reached after 0.17 s
  const double ticks_per_m =
      static_cast<double>(profile.ticks_per_wheel_rev) / (2 * kPi * profile.wheel_radius_m);
  const double encoder_m = static_cast<double>(sim.read_encoders().left_ticks) / ticks_per_m;
  EXPECT_NEAR(encoder_m, 2.0, 0.002);
  EXPECT_NEAR(sim.true_pose().x - 2.0, 2.0 - 0.5 * 0.5 / (2 * 3.0), 0.002);
  const double before_stop_m = sim.true_pose().x;
  drive(sim, 0.0, 0.0, 1.0);
  EXPECT_NEAR(sim.true_pose().x - before_stop_m, 0.5 * 0.5 / (2 * 3.0), 0.002) << "skids 4 cm";
  EXPECT_NEAR(static_cast<double>(sim.read_encoders().left_ticks) / ticks_per_m, encoder_m,
              1.0 / ticks_per_m);
  // Within the R2 ramp (0.3 m/s^2) nothing slips.
  Simulator gentle(builtin("office"), profile, 1);
  for (int i = 1; i <= 50; ++i) {
    gentle.set_command({0.3 * i / 50.0, 0.0});
    gentle.step(kDt_s);
  }
  const double gentle_encoder_m =
      static_cast<double>(gentle.read_encoders().right_ticks) / ticks_per_m;
  EXPECT_NEAR(gentle.true_pose().x - 2.0, gentle_encoder_m, 2.0 / ticks_per_m);
}

// Drives legs on its own odometry, as a base with no other sensor would, with the R2 ramp: each
// leg straight on for `side_m`, then a turn on the spot by `turn_rad`. Returns how far the
// odometry's idea of the end is from the truth.
struct LoopResult {
  double end_error_m = 0.0;
  double heading_error_rad = 0.0;         // odometry minus truth at the end
  double straight_drift_rad_per_m = 0.0;  // heading error gained on the straights, per metre
  double distance_m = 0.0;
  int collisions = 0;
};

LoopResult drive_on_odometry(const RobotProfile& profile, std::uint64_t seed,
                             const geometry::Pose2D& start, int legs, double side_m,
                             double turn_rad) {
  Simulator sim(builtin("office"), profile, seed);
  sim.reset(start, seed);
  estimation::WheelOdometry odometry(
      {profile.wheel_radius_m, profile.wheel_radius_m, profile.track_m,
       static_cast<int>(profile.ticks_per_wheel_rev)},
      start);
  odometry.update(sim.read_encoders());
  control::VelocitySmoother smoother({0.3, 0.5, 0.3, 0.3});
  LoopResult result;
  const auto heading_error = [&] {
    return geometry::wrap_angle(odometry.odometry().pose.theta - sim.true_pose().theta);
  };
  const auto tick = [&](const msgs::Twist& target) {
    sim.set_command(smoother.step(target, kDt_s));
    sim.step(kDt_s);
    odometry.update(sim.read_encoders());
  };
  const auto settle = [&] {
    for (int i = 0; i < 100; ++i) tick({});
  };
  for (int leg = 1; leg <= legs; ++leg) {
    const geometry::Pose2D from = odometry.odometry().pose;
    const double heading = from.theta;
    const double error_before = heading_error();
    const double travelled_before = odometry.travelled_m();
    // Straight on: hold the heading the odometry had at the corner.
    for (int i = 0; i < 100000; ++i) {
      const geometry::Pose2D now = odometry.odometry().pose;
      const double along =
          (now.x - from.x) * std::cos(heading) + (now.y - from.y) * std::sin(heading);
      const double left = side_m - along;
      if (left < 0.002) break;
      const double cross =
          -(now.x - from.x) * std::sin(heading) + (now.y - from.y) * std::cos(heading);
      // Slowing down within the ramp's 0.3 m/s^2, so the base stops where it is told.
      tick({std::clamp(std::sqrt(2.0 * 0.25 * left), 0.02, 0.3),
            std::clamp(-2.0 * geometry::wrap_angle(now.theta - heading) - 3.0 * cross, -0.5, 0.5)});
    }
    settle();
    result.straight_drift_rad_per_m += heading_error() - error_before;
    result.distance_m += odometry.travelled_m() - travelled_before;
    // Counted as it goes, so a half turn is a left turn, not whichever way wraps shorter.
    double turned_rad = 0.0;
    double last_theta = odometry.odometry().pose.theta;
    const double target_rad = turn_rad + geometry::wrap_angle(heading - last_theta);
    for (int i = 0; i < 100000; ++i) {
      const double left = target_rad - turned_rad;
      if (std::abs(left) < 0.002) break;
      tick({0.0,
            std::copysign(std::clamp(std::sqrt(2.0 * 0.25 * std::abs(left)), 0.02, 0.5), left)});
      turned_rad += geometry::wrap_angle(odometry.odometry().pose.theta - last_theta);
      last_theta = odometry.odometry().pose.theta;
    }
    settle();
  }
  result.straight_drift_rad_per_m /= legs * side_m;
  const geometry::Pose2D odom = odometry.odometry().pose;
  result.end_error_m = std::hypot(odom.x - sim.true_pose().x, odom.y - sim.true_pose().y);
  result.heading_error_rad = heading_error();
  result.collisions = sim.collision_count();
  return result;
}

// From the office's start, 10 m east along the main corridor, a U-turn on the spot, and back.
LoopResult corridor_loop(const RobotProfile& profile, std::uint64_t seed) {
  return drive_on_odometry(profile, seed, {3.0, 7.5, 0.0}, 2, 10.0, kPi);
}

// Twice round a 2.5 m square counter-clockwise in the middle of room N2 (x 7..13, y 8.65..14.8),
// 20 m with 1.5 m to every wall: room for what the odometry does not know.
LoopResult room_loop(const RobotProfile& profile, std::uint64_t seed) {
  return drive_on_odometry(profile, seed, {8.75, 10.475, 0.0}, 8, 2.5, kPi / 2);
}

TEST(DashgoD1, StraightRunsDriftByTheConfiguredHeadingDrift) {
  // Without the slip noise only the systematic errors remain: the truth turns left of the
  // odometry by 0.004 rad per true metre, 0.004 / 1.01 per metre the odometry reads.
  RobotProfile profile = dashgo_d1_profile();
  set_odometry_errors(profile, {0.01, 0.004, 0.0});
  for (int seed = 1; seed <= 3; ++seed) {
    const LoopResult loop = corridor_loop(profile, seed);
    EXPECT_NEAR(loop.straight_drift_rad_per_m, -0.004 / 1.01, 0.0003) << "seed " << seed;
    // Each of the two U-turns comes out 1 % short (smaller wheels, same track): pi / 101 to the
    // right.
    EXPECT_NEAR(loop.heading_error_rad - loop.straight_drift_rad_per_m * loop.distance_m,
                2 * (kPi - kPi / 1.01), 0.004)
        << "seed " << seed;
  }
}

TEST(DashgoD1, OdometryAloneDriftsOverATwentyMetreLoopLikeARealBase) {
  constexpr int kSeeds = 10;
  double sum_error = 0.0;
  double max_error = 0.0;
  double sum_drift = 0.0;
  double sum_heading = 0.0;
  double sum_heading_sq = 0.0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const LoopResult loop = room_loop(dashgo_d1_profile(), seed);
    EXPECT_EQ(loop.collisions, 0) << "seed " << seed;
    EXPECT_NEAR(loop.distance_m, 20.0, 0.05) << "seed " << seed;
    std::cout << std::fixed << std::setprecision(4) << "[ loop seed " << std::setw(2) << seed
              << " ] end error " << loop.end_error_m << " m, heading error "
              << loop.heading_error_rad << " rad, straight drift " << loop.straight_drift_rad_per_m
              << " rad/m" << std::endl;
    sum_error += loop.end_error_m;
    max_error = std::max(max_error, loop.end_error_m);
    sum_drift += loop.straight_drift_rad_per_m;
    sum_heading += loop.heading_error_rad;
    sum_heading_sq += loop.heading_error_rad * loop.heading_error_rad;
  }
  const double mean_drift = sum_drift / kSeeds;
  const double mean_heading = sum_heading / kSeeds;
  const double heading_spread =
      std::sqrt(std::max(0.0, sum_heading_sq / kSeeds - mean_heading * mean_heading));
  std::cout << "[ loop ] mean end error " << sum_error / kSeeds << " m (max " << max_error
            << "), straight-run heading drift " << mean_drift << " rad/m, end heading error "
            << mean_heading << " +- " << heading_spread << " rad (" << mean_heading / 20.0
            << " rad/m)" << std::endl;
  // The systematic drift shows through the slip noise (about 0.003 rad/m per seed over 20 m of
  // straights, so 0.001 for the mean of ten loops).
  EXPECT_NEAR(mean_drift, -0.004, 0.003);
  // Not a perfect base, and not a broken one: decimetres after 20 m.
  EXPECT_GT(sum_error / kSeeds, 0.05);
  EXPECT_LT(max_error, 1.5);
  EXPECT_GT(heading_spread, 0.01) << "the slip noise differs from seed to seed";
}

}  // namespace
}  // namespace mobot::sim
