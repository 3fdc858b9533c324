#include "core/estimation/ekf_localizer.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "core/kinematics/diff_drive.h"
#include "core/mapping/occupancy_grid.h"
#include "core/perception/line_extractor.h"
#include "core/perception/map_line_extractor.h"
#include "tests/unit/core/estimation/synthetic_world.h"

namespace mobot::estimation {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTrack = 0.6;
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

using estimation_sim::rectangle_room;
using estimation_sim::ScanSpec;
using estimation_sim::simulate_scan;
using estimation_sim::Wall;
using estimation_sim::wall_lines;

Eigen::Matrix3d diag(double a, double b, double c) { return Eigen::Vector3d(a, b, c).asDiagonal(); }

bool same_state(const EkfLocalizer& a, const geometry::Pose2D& pose, const Eigen::Matrix3d& cov) {
  return a.pose() == pose && a.covariance() == cov;
}

TEST(EkfLocalizer, PredictFollowsOdometryAndGrowsCovariance) {
  EkfLocalizer ekf({}, {1.0, 2.0, 0.5}, diag(1e-4, 1e-4, 1e-4));
  ASSERT_TRUE(ekf.predict(0.11, 0.09, kTrack).applied());
  const auto expected = kinematics::integrate_wheel_travel({1.0, 2.0, 0.5}, 0.09, 0.11, kTrack);
  EXPECT_NEAR(ekf.pose().x, expected.x, 1e-12);
  EXPECT_NEAR(ekf.pose().y, expected.y, 1e-12);
  EXPECT_NEAR(ekf.pose().theta, expected.theta, 1e-12);
  const Eigen::Matrix3d expected_cov = propagate_odometry_covariance(
      diag(1e-4, 1e-4, 1e-4), {1.0, 2.0, 0.5}, 0.09, 0.11, kTrack, WheelNoise{});
  EXPECT_TRUE(ekf.covariance().isApprox(expected_cov, 1e-12));
  // Standing still adds no uncertainty.
  const Eigen::Matrix3d before = ekf.covariance();
  ekf.predict(0.0, 0.0, kTrack);
  EXPECT_TRUE(ekf.covariance().isApprox(before, 1e-15));
}

TEST(EkfLocalizer, CompassUpdateShrinksHeadingVariance) {
  EkfLocalizer ekf({}, {0.0, 0.0, 0.1}, diag(0.01, 0.01, 0.01));
  const auto report = ekf.update_compass(0.2);
  ASSERT_TRUE(report.applied());
  EXPECT_EQ(report.rows_used, 1);
  const double gain = 0.01 / (0.01 + 2.79e-4);
  EXPECT_NEAR(ekf.pose().theta, 0.1 + gain * 0.1, 1e-12);
  EXPECT_NEAR(ekf.covariance()(2, 2), (1 - gain) * 0.01, 1e-12);
  EXPECT_NEAR(ekf.covariance()(0, 0), 0.01, 1e-15);
}

TEST(EkfLocalizer, CompassInnovationWrapsAroundPi) {
  EkfLocalizer ekf({}, {0.0, 0.0, kPi - 0.01}, diag(0.01, 0.01, 0.01));
  ASSERT_TRUE(ekf.update_compass(-kPi + 0.01).applied());
  // The estimate moves 0.02 rad the short way round (across pi), not 2 pi - 0.02 back.
  const double moved = geometry::wrap_angle(ekf.pose().theta - (kPi - 0.01));
  EXPECT_GT(moved, 0.015);
  EXPECT_LT(moved, 0.02);
  EXPECT_LE(std::abs(ekf.pose().theta), kPi);
}

TEST(EkfLocalizer, BearingInnovationWrapsAroundPi) {
  // Landmark straight behind the robot.
  EkfLocalizer ekf({}, {0.0, 0.0, 0.0}, diag(0.01, 0.01, 0.01));
  ASSERT_TRUE(ekf.update_bearing(-kPi + 0.01, {-5.0, 0.0}).applied());
  // Bearing pi + 0.01 (wrapped): the heading must be a little less than thought, by at most the
  // 0.01 rad innovation, not by 2 pi - 0.01.
  EXPECT_LT(ekf.pose().theta, 0.0);
  EXPECT_GT(ekf.pose().theta, -0.011);
}

TEST(EkfLocalizer, NonFiniteInputsAreRejectedAndChangeNothing) {
  const geometry::Pose2D pose{1.0, 2.0, 0.3};
  const Eigen::Matrix3d cov = diag(0.01, 0.02, 0.03);
  EkfLocalizer ekf({}, pose, cov);
  const auto map = wall_lines(rectangle_room(0, 0, 10, 8));
  perception::LineSegment bad_line = map[0];
  bad_line.var_rho_m2 = kNan;

  EXPECT_EQ(ekf.predict(kNan, 0.1, kTrack).status, UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.predict(0.1, std::numeric_limits<double>::infinity(), kTrack).status,
            UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.predict(0.1, 0.1, 0.0).status, UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.update_compass(kNan).status, UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.update_bearing(kNan, {1, 1}).status, UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.update_bearing(0.1, {kNan, 1}).status, UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.update_lines({bad_line}, {}, map).update.status, UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.update_lines({map[0]}, {kNan, 0, 0}, map).update.status,
            UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.update_lines({map[0]}, {}, {bad_line}).update.status,
            UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.set_pose({kNan, 0, 0}, cov).status, UpdateStatus::kRejectedNonFinite);
  Eigen::Matrix3d nan_cov = cov;
  nan_cov(1, 2) = kNan;
  EXPECT_EQ(ekf.set_pose(pose, nan_cov).status, UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.set_pose(pose, diag(-1, 1, 1)).status, UpdateStatus::kRejectedNonFinite);
  EXPECT_TRUE(same_state(ekf, pose, cov));
  // On the landmark the bearing is undefined.
  EXPECT_EQ(ekf.update_bearing(0.1, {1.0, 2.0}).status, UpdateStatus::kNumericalFailure);
  EXPECT_TRUE(same_state(ekf, pose, cov));
}

TEST(EkfLocalizer, DegenerateUpdatesAreReported) {
  // A certain filter and a noise-free compass: S = 0.
  EkfLocalizerOptions options;
  options.compass_var_rad2 = 0.0;
  EkfLocalizer ekf(options);
  EXPECT_EQ(ekf.update_compass(0.1).status, UpdateStatus::kNumericalFailure);
  EXPECT_EQ(ekf.pose().theta, 0.0);
  // Nothing to match.
  EkfLocalizer lines({}, {3, 2, 0}, diag(0.01, 0.01, 0.01));
  const auto report = lines.update_lines({}, {}, wall_lines(rectangle_room(0, 0, 10, 8)));
  EXPECT_EQ(report.update.status, UpdateStatus::kNoMatch);
  EXPECT_TRUE(report.matches.empty());
  EXPECT_EQ(lines.update_lines({}, {}, {}).update.status, UpdateStatus::kNoMatch);
}

TEST(EkfLocalizer, CompassGateRejectsOutliersWhenEnabled) {
  EkfLocalizerOptions options;
  options.compass_gate_chi2 = 10.83;  // 99.9 %, 1 dof
  EkfLocalizer ekf(options, {0, 0, 0}, diag(0.01, 0.01, 1e-4));
  const auto report = ekf.update_compass(0.5);
  EXPECT_EQ(report.status, UpdateStatus::kRejectedOutlier);
  EXPECT_GT(report.nis, 10.83);
  EXPECT_EQ(ekf.pose().theta, 0.0);
  EXPECT_TRUE(ekf.update_compass(0.01).applied());
}

TEST(EkfLocalizer, SetPoseReinitialises) {
  EkfLocalizer ekf;
  ASSERT_TRUE(ekf.set_pose({1, 2, 3 * kPi}, diag(1, 2, 3)).applied());
  EXPECT_NEAR(ekf.pose().theta, kPi, 1e-12);
  EXPECT_EQ(ekf.covariance(), diag(1, 2, 3));
}

// The laser's mounting offset must be taken into account: with it, lines pull the estimate onto
// the truth; pretending the laser sits at the centre leaves a bias of about the offset.
TEST(EkfLocalizer, LineUpdateUsesTheSensorMounting) {
  const std::vector<Wall> walls = rectangle_room(0.0, 0.0, 10.0, 8.0);
  const auto map = wall_lines(walls);
  const geometry::Pose2D truth{3.0, 2.0, 0.5};
  const geometry::Pose2D mount{0.3, 0.1, 0.2};
  ScanSpec spec;
  spec.fov_rad = 2 * kPi;
  spec.beams = 720;
  const auto scan = simulate_scan(walls, truth, mount, spec);
  const auto lines = perception::LineExtractor().extract(scan);
  ASSERT_GE(lines.size(), 3U);

  const geometry::Pose2D start{3.1, 1.95, 0.55};
  EkfLocalizer with_mount({}, start, diag(0.02, 0.02, 0.01));
  EkfLocalizer without({}, start, diag(0.02, 0.02, 0.01));
  for (int i = 0; i < 3; ++i) {
    const auto report = with_mount.update_lines(lines, mount, map);
    ASSERT_TRUE(report.update.applied()) << to_string(report.update.status);
    EXPECT_EQ(report.update.rows_used, 2 * static_cast<int>(report.matches.size()));
    without.update_lines(lines, {}, map);
  }
  EXPECT_LT(std::hypot(with_mount.pose().x - truth.x, with_mount.pose().y - truth.y), 0.005);
  EXPECT_LT(std::abs(geometry::wrap_angle(with_mount.pose().theta - truth.theta)), 0.002);
  EXPECT_GT(std::hypot(without.pose().x - truth.x, without.pose().y - truth.y) +
                std::abs(geometry::wrap_angle(without.pose().theta - truth.theta)),
            0.1);
}

// The runtime's pipeline end to end: map lines from an occupancy grid, lines from a scan of the
// same walls, the EKF pulled onto the truth. Catches any disagreement of frames or face offsets.
TEST(EkfLocalizer, LocalisesAgainstLinesFromAnOccupancyGrid) {
  using mapping::OccupancyGrid;
  const geometry::Pose2D origin{-1.0, -0.5, 0.0};
  OccupancyGrid grid(120, 80, 0.05, origin, OccupancyGrid::kUnknown);
  for (int y = 10; y < 70; ++y) {
    for (int x = 10; x < 110; ++x) {
      const bool wall =
          x < 12 || x >= 108 || y < 12 || y >= 68 || (x >= 50 && x < 60 && y >= 30 && y < 40);
      grid.set({x, y}, wall ? OccupancyGrid::kOccupied : OccupancyGrid::kFree);
    }
  }
  const auto map = perception::extract_map_lines(grid);
  ASSERT_EQ(map.size(), 8U);
  // The same faces as geometry: room interior x in [0.6, 5.4] - 1, y in [0.6, 3.4] - 0.5; the
  // pillar x in [2.5, 3.0] - 1, y in [1.5, 2.0] - 0.5.
  std::vector<Wall> walls = rectangle_room(-0.4, 0.1, 4.4, 2.9);
  const auto pillar = rectangle_room(1.5, 1.0, 2.0, 1.5);
  walls.insert(walls.end(), pillar.begin(), pillar.end());

  const geometry::Pose2D truth{0.5, 0.5, 0.3};
  const geometry::Pose2D mount{0.2, 0.0, 0.0};
  ScanSpec spec;
  spec.range_sigma_m = 0.01;
  std::mt19937 rng(23);
  EkfLocalizer ekf({}, {0.65, 0.38, 0.36}, diag(0.04, 0.04, 0.01));
  for (int i = 0; i < 5; ++i) {
    const auto scan = simulate_scan(walls, truth, mount, spec, &rng);
    const auto report = ekf.update_lines(perception::LineExtractor().extract(scan), mount, map);
    EXPECT_TRUE(report.update.applied()) << to_string(report.update.status);
  }
  EXPECT_LT(std::hypot(ekf.pose().x - truth.x, ekf.pose().y - truth.y), 0.01);
  EXPECT_LT(std::abs(geometry::wrap_angle(ekf.pose().theta - truth.theta)), 0.005);
}

// ---- Synthetic runs: E2's measurement sets on a loop through a room with a pillar ----------

enum class Sensors { kOdometry, kCompass, kCompassLines, kCompassLinesBearing };

struct RunStats {
  double rmse_position_m = 0.0;
  double mean_nees = 0.0;
  double final_error_m = 0.0;
  int line_updates = 0;
};

std::vector<Wall> room_with_pillar() {
  std::vector<Wall> walls = rectangle_room(0.0, 0.0, 10.0, 8.0);
  const auto pillar = rectangle_room(4.5, 3.5, 5.5, 4.5);
  walls.insert(walls.end(), pillar.begin(), pillar.end());
  return walls;
}

// Wheel travel (left, right) per 0.1 s step of a rounded-rectangle loop at 0.3 m/s.
std::vector<std::pair<double, double>> loop_steps(int loops) {
  const double step_m = 0.03;
  std::vector<std::pair<double, double>> steps;
  auto straight = [&](double length_m) {
    for (int i = 0; i < static_cast<int>(std::round(length_m / step_m)); ++i) {
      steps.emplace_back(step_m, step_m);
    }
  };
  auto arc_left = [&](double radius_m) {
    const double length_m = radius_m * kPi / 2;
    const int n = static_cast<int>(std::round(length_m / step_m));
    const double dtheta = (kPi / 2) / n;
    const double ds = length_m / n;
    for (int i = 0; i < n; ++i) {
      steps.emplace_back(ds - dtheta * kTrack / 2, ds + dtheta * kTrack / 2);
    }
  };
  for (int loop = 0; loop < loops; ++loop) {
    straight(4.0);
    arc_left(0.5);
    straight(3.0);
    arc_left(0.5);
    straight(4.0);
    arc_left(0.5);
    straight(3.0);
    arc_left(0.5);
  }
  return steps;
}

RunStats run(Sensors sensors, unsigned seed) {
  const std::vector<Wall> walls = room_with_pillar();
  const auto map = wall_lines(walls);
  const std::vector<geometry::Point2D> landmarks = {{0.5, 7.5}, {9.5, 0.5}, {9.5, 7.5}};
  const geometry::Pose2D mount{0.25, 0.0, 0.0};
  const perception::LineExtractor extractor;
  ScanSpec spec;
  spec.range_sigma_m = 0.01;

  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  const WheelNoise noise;
  const EkfLocalizerOptions options;
  geometry::Pose2D truth{3.0, 2.0, 0.0};
  // The filter starts from a draw of its own initial covariance.
  const Eigen::Matrix3d initial = diag(1e-4, 1e-4, 1e-5);
  EkfLocalizer ekf(options,
                   {truth.x + 1e-2 * unit(rng), truth.y + 1e-2 * unit(rng),
                    truth.theta + std::sqrt(1e-5) * unit(rng)},
                   initial);

  RunStats stats;
  double sum_sq = 0.0;
  double sum_nees = 0.0;
  int n = 0;
  for (const auto& [left_m, right_m] : loop_steps(2)) {
    truth = kinematics::integrate_wheel_travel(truth, left_m, right_m, kTrack);
    // Encoders with exactly the noise the filter assumes.
    const double measured_left = left_m + unit(rng) * std::sqrt(noise.k_left * std::abs(left_m));
    const double measured_right =
        right_m + unit(rng) * std::sqrt(noise.k_right * std::abs(right_m));
    EXPECT_TRUE(ekf.predict(measured_right, measured_left, kTrack).applied());

    if (sensors != Sensors::kOdometry) {
      ekf.update_compass(truth.theta + unit(rng) * std::sqrt(options.compass_var_rad2));
    }
    if (sensors == Sensors::kCompassLines || sensors == Sensors::kCompassLinesBearing) {
      const auto scan = simulate_scan(walls, truth, mount, spec, &rng);
      if (ekf.update_lines(extractor.extract(scan), mount, map).update.applied()) {
        ++stats.line_updates;
      }
    }
    if (sensors == Sensors::kCompassLinesBearing) {
      for (const auto& landmark : landmarks) {
        const double bearing = std::atan2(landmark.y - truth.y, landmark.x - truth.x) -
                               truth.theta + unit(rng) * std::sqrt(options.bearing_var_rad2);
        ekf.update_bearing(geometry::wrap_angle(bearing), landmark);
      }
    }
    const Eigen::Vector3d error(truth.x - ekf.pose().x, truth.y - ekf.pose().y,
                                geometry::wrap_angle(truth.theta - ekf.pose().theta));
    sum_sq += error.head<2>().squaredNorm();
    sum_nees += error.dot(ekf.covariance().ldlt().solve(error));
    ++n;
    stats.final_error_m = error.head<2>().norm();
  }
  const auto steps = static_cast<double>(loop_steps(2).size());
  stats.rmse_position_m = std::sqrt(sum_sq / steps);
  stats.mean_nees = n > 0 ? sum_nees / n : 0.0;
  return stats;
}

RunStats average(Sensors sensors, int runs) {
  RunStats total;
  for (int seed = 1; seed <= runs; ++seed) {
    const RunStats one = run(sensors, static_cast<unsigned>(seed));
    total.rmse_position_m += one.rmse_position_m / runs;
    total.mean_nees += one.mean_nees / runs;
    total.final_error_m += one.final_error_m / runs;
    total.line_updates += one.line_updates;
  }
  return total;
}

TEST(EkfLocalizerRun, EachMeasurementSetImprovesOnTheLast) {
  const int runs = 5;
  const RunStats odometry = average(Sensors::kOdometry, runs);
  const RunStats compass = average(Sensors::kCompass, runs);
  const RunStats lines = average(Sensors::kCompassLines, runs);
  const RunStats all = average(Sensors::kCompassLinesBearing, runs);
  std::printf("RMSE position (m) / mean NEES over %d runs of 2 loops (34 m):\n", runs);
  std::printf("  odometry only         %.3f / %.2f\n", odometry.rmse_position_m,
              odometry.mean_nees);
  std::printf("  + compass             %.3f / %.2f\n", compass.rmse_position_m, compass.mean_nees);
  std::printf("  + laser lines         %.3f / %.2f (%d line updates)\n", lines.rmse_position_m,
              lines.mean_nees, lines.line_updates);
  std::printf("  + landmark bearings   %.3f / %.2f\n", all.rmse_position_m, all.mean_nees);

  EXPECT_LT(compass.rmse_position_m, 0.7 * odometry.rmse_position_m);
  EXPECT_LT(lines.rmse_position_m, 0.2 * compass.rmse_position_m);
  EXPECT_LT(lines.rmse_position_m, 0.03);
  EXPECT_LE(all.rmse_position_m, lines.rmse_position_m * 1.05);
  // Lines must have been used on nearly every scan.
  EXPECT_GT(lines.line_updates, runs * static_cast<int>(loop_steps(2).size()) * 9 / 10);
  // Consistency: the average NEES of a 3-state filter should be about 3; not overconfident.
  for (const RunStats* s : {&odometry, &compass, &lines, &all}) {
    EXPECT_LT(s->mean_nees, 6.0);
    EXPECT_GT(s->mean_nees, 0.5);
  }
}

// From a wrong start, each absolute measurement set pulls the estimate in.
TEST(EkfLocalizerRun, ConvergesFromAnOffsetStart) {
  const std::vector<Wall> walls = room_with_pillar();
  const auto map = wall_lines(walls);
  const std::vector<geometry::Point2D> landmarks = {{0.5, 7.5}, {9.5, 0.5}, {9.5, 7.5}};
  const perception::LineExtractor extractor;
  std::mt19937 rng(17);
  std::normal_distribution<double> unit(0.0, 1.0);
  ScanSpec spec;
  spec.range_sigma_m = 0.01;
  const geometry::Pose2D wrong_start{3.3, 1.8, 0.12};
  const Eigen::Matrix3d start_cov = diag(0.09, 0.09, 0.02);

  for (const bool use_lines : {false, true}) {
    geometry::Pose2D truth{3.0, 2.0, 0.0};
    EkfLocalizer ekf({}, wrong_start, start_cov);
    const auto steps = loop_steps(1);
    for (std::size_t k = 0; k < 200; ++k) {
      const auto [left_m, right_m] = steps[k];
      truth = kinematics::integrate_wheel_travel(truth, left_m, right_m, kTrack);
      ekf.predict(right_m, left_m, kTrack);
      if (use_lines) {
        ekf.update_lines(extractor.extract(simulate_scan(walls, truth, {}, spec, &rng)), {}, map);
      } else {
        for (const auto& landmark : landmarks) {
          const double bearing = std::atan2(landmark.y - truth.y, landmark.x - truth.x) -
                                 truth.theta + unit(rng) * std::sqrt(2.992e-4);
          ekf.update_bearing(geometry::wrap_angle(bearing), landmark);
        }
      }
    }
    const double error_m = std::hypot(ekf.pose().x - truth.x, ekf.pose().y - truth.y);
    const double heading_error = std::abs(geometry::wrap_angle(ekf.pose().theta - truth.theta));
    EXPECT_LT(error_m, use_lines ? 0.01 : 0.05) << (use_lines ? "lines" : "bearings");
    EXPECT_LT(heading_error, use_lines ? 0.005 : 0.02) << (use_lines ? "lines" : "bearings");
    EXPECT_LT(ekf.covariance()(0, 0), start_cov(0, 0) / 10);
  }
}

}  // namespace
}  // namespace mobot::estimation
