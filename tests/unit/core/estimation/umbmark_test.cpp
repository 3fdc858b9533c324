#include "core/estimation/umbmark.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "core/kinematics/diff_drive.h"

namespace mobot::estimation {
namespace {

constexpr double kPi = std::numbers::pi;

// The robot executes moves by its odometry (nominal params): it turns each wheel by the angle its
// odometry needs. The real wheels (true params) then roll radius x angle; the true path is
// integrated in small steps.
struct Robot {
  OdometryParams nominal;
  OdometryParams truth;
  geometry::Pose2D pose;

  void wheels(double left_odometry_m, double right_odometry_m) {
    const int substeps = 200;
    const double left_m =
        left_odometry_m / nominal.left_wheel_radius_m * truth.left_wheel_radius_m / substeps;
    const double right_m =
        right_odometry_m / nominal.right_wheel_radius_m * truth.right_wheel_radius_m / substeps;
    for (int i = 0; i < substeps; ++i) {
      pose = kinematics::integrate_wheel_travel(pose, left_m, right_m, truth.track_m);
    }
  }
  void straight(double length_m) { wheels(length_m, length_m); }
  // Turn in place by angle_rad according to the odometry.
  void turn(double angle_rad) {
    const double arc_m = angle_rad * nominal.track_m / 2.0;
    wheels(-arc_m, arc_m);
  }
};

// One UMBmark run from (0, 0, 0); the odometry believes it returns exactly to the start, so the
// error is where the robot really stopped.
UmbmarkRunError square_run(const OdometryParams& nominal, const OdometryParams& truth,
                           double side_m, bool clockwise) {
  Robot robot{nominal, truth, {}};
  for (int leg = 0; leg < 4; ++leg) {
    robot.straight(side_m);
    robot.turn(clockwise ? -kPi / 2 : kPi / 2);
  }
  return {robot.pose.x, robot.pose.y};
}

double straight_error_percent(const OdometryParams& nominal, const OdometryParams& truth,
                              double length_m) {
  Robot robot{nominal, truth, {}};
  robot.straight(length_m);
  return straight_run_error_percent({length_m, 0.0}, {robot.pose.x, robot.pose.y}, length_m);
}

OdometryParams params(double left_m, double right_m, double track_m) {
  OdometryParams p;
  p.left_wheel_radius_m = left_m;
  p.right_wheel_radius_m = right_m;
  p.track_m = track_m;
  return p;
}

TEST(Umbmark, CorrectsSimulatedSystematicErrors) {
  const OdometryParams nominal = params(0.1, 0.1, 0.6);
  // Right wheel 0.66 % larger than the left (same mean), real track 2 % wider than believed.
  const OdometryParams truth = params(0.1 * (1 - 0.0033), 0.1 * (1 + 0.0033), 0.612);
  const double side_m = 4.0;
  const int runs = 5;
  std::mt19937 rng(1);
  std::normal_distribution<double> measurement(0.0, 0.005);  // how well the stop is measured
  std::vector<UmbmarkRunError> cw;
  std::vector<UmbmarkRunError> ccw;
  for (int i = 0; i < runs; ++i) {
    const auto e_cw = square_run(nominal, truth, side_m, true);
    const auto e_ccw = square_run(nominal, truth, side_m, false);
    cw.push_back({e_cw.x_m + measurement(rng), e_cw.y_m + measurement(rng)});
    ccw.push_back({e_ccw.x_m + measurement(rng), e_ccw.y_m + measurement(rng)});
  }
  const auto result = umbmark_calibrate(nominal, side_m, cw, ccw);
  ASSERT_TRUE(result.has_value());

  EXPECT_NEAR(result->diameter_ratio, (1 + 0.0033) / (1 - 0.0033), 5e-4);
  EXPECT_NEAR(result->wheelbase_factor, 0.612 / 0.6, 2e-3);
  EXPECT_NEAR(result->corrected.track_m, 0.612, 1.5e-3);
  EXPECT_NEAR(result->left_radius_factor + result->right_radius_factor, 2.0, 1e-12);
  EXPECT_NEAR(result->corrected.right_wheel_radius_m / result->corrected.left_wheel_radius_m,
              truth.right_wheel_radius_m / truth.left_wheel_radius_m, 5e-4);
  EXPECT_EQ(result->corrected.ticks_per_wheel_rev, nominal.ticks_per_wheel_rev);

  // E1's before/after: a 7 m straight run.
  const double before = straight_error_percent(nominal, truth, 7.0);
  const double after = straight_error_percent(result->corrected, truth, 7.0);
  std::printf("UMBmark: 7 m straight run error %.2f %% -> %.3f %%; E_d %.5f, E_b %.5f\n", before,
              after, result->diameter_ratio, result->wheelbase_factor);
  EXPECT_GT(before, 3.0);
  EXPECT_LT(before, 5.0);
  EXPECT_LT(after, 0.3);

  // And the squares themselves close far better with the corrected parameters.
  const auto cw_after = square_run(result->corrected, truth, side_m, true);
  const auto ccw_after = square_run(result->corrected, truth, side_m, false);
  EXPECT_LT(
      std::max(std::hypot(cw_after.x_m, cw_after.y_m), std::hypot(ccw_after.x_m, ccw_after.y_m)),
      0.1 * result->systematic_error_m);
}

// Borenstein's x formulas on the first-order error model: CW (x, y) = -2L(a + b) (1, 1),
// CCW = 2L(b - a) (1, -1).
TEST(Umbmark, RecoversAlphaAndBetaFromTheErrorModel) {
  const double side = 4.0;
  const double alpha = 0.01;
  const double beta = -0.004;
  const std::vector<UmbmarkRunError> cw = {
      {-2 * side * (alpha + beta), -2 * side * (alpha + beta)}};
  const std::vector<UmbmarkRunError> ccw = {
      {2 * side * (beta - alpha), -2 * side * (beta - alpha)}};
  const auto result = umbmark_calibrate(params(0.1, 0.1, 0.6), side, cw, ccw);
  ASSERT_TRUE(result.has_value());
  EXPECT_NEAR(result->alpha_rad, alpha, 1e-12);
  EXPECT_NEAR(result->beta_rad, beta, 1e-12);
  EXPECT_NEAR(result->wheelbase_factor, (kPi / 2) / (kPi / 2 - alpha), 1e-12);
  // beta < 0 curves right: the left wheel is the larger one.
  EXPECT_LT(result->diameter_ratio, 1.0);
}

TEST(Umbmark, PerfectRunsChangeNothing) {
  const std::vector<UmbmarkRunError> zero(3);
  const OdometryParams p = params(0.1, 0.1, 0.6);
  const auto result = umbmark_calibrate(p, 4.0, zero, zero);
  ASSERT_TRUE(result.has_value());
  EXPECT_DOUBLE_EQ(result->diameter_ratio, 1.0);
  EXPECT_DOUBLE_EQ(result->wheelbase_factor, 1.0);
  EXPECT_DOUBLE_EQ(result->corrected.left_wheel_radius_m, 0.1);
  EXPECT_DOUBLE_EQ(result->corrected.track_m, 0.6);
}

TEST(Umbmark, RejectsBadInput) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const OdometryParams p = params(0.1, 0.1, 0.6);
  const std::vector<UmbmarkRunError> ok = {{0.01, 0.02}};
  const std::vector<UmbmarkRunError> bad = {{nan, 0.0}};
  const std::vector<UmbmarkRunError> none;
  EXPECT_FALSE(umbmark_calibrate(p, 4.0, bad, ok).has_value());
  EXPECT_FALSE(umbmark_calibrate(p, 4.0, ok, none).has_value());
  EXPECT_FALSE(umbmark_calibrate(p, 0.0, ok, ok).has_value());
  EXPECT_FALSE(umbmark_calibrate(p, nan, ok, ok).has_value());
  EXPECT_FALSE(umbmark_calibrate(params(0.1, -0.1, 0.6), 4.0, ok, ok).has_value());
  // Errors far beyond the small-error model: alpha past 90 deg...
  const std::vector<UmbmarkRunError> huge = {{-30.0, 0.0}};
  EXPECT_FALSE(umbmark_calibrate(p, 4.0, huge, huge).has_value());
  // ...or a curvature radius under half the track.
  const std::vector<UmbmarkRunError> cw_curl = {{-30.0, -30.0}};
  const std::vector<UmbmarkRunError> ccw_curl = {{30.0, -30.0}};
  EXPECT_FALSE(umbmark_calibrate(params(0.1, 0.1, 8.0), 4.0, cw_curl, ccw_curl).has_value());
  EXPECT_TRUE(std::isnan(straight_run_error_percent({7, 0}, {7, 0.1}, 0.0)));
  EXPECT_NEAR(straight_run_error_percent({7, 0}, {7, 0.07}, 7.0), 1.0, 1e-12);
}

}  // namespace
}  // namespace mobot::estimation
