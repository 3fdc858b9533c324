#include "core/estimation/landmark_ekf.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "core/estimation/tricycle_motion_model.h"

namespace mobot::estimation {
namespace {

constexpr double kPi = std::numbers::pi;

Eigen::Matrix3d diag(double a, double b, double c) { return Eigen::Vector3d(a, b, c).asDiagonal(); }

// The true tricycle, integrated finely; the filter gets noisy (v, alpha) and noisy range-bearing
// observations of the landmarks every 0.1 s (E3's sigmas).
struct Outcome {
  double rmse_m = 0.0;
  double final_error_m = 0.0;
  double final_heading_error_rad = 0.0;
  double mean_nees = 0.0;
  double dead_reckoning_error_m = 0.0;
};

Outcome simulate(const std::vector<geometry::Point2D>& landmarks, unsigned seed,
                 const LandmarkEkfOptions& options = {},
                 std::vector<double>* nees_per_step = nullptr) {
  const double dt = 0.1;
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  geometry::Pose2D truth{0.0, 0.0, 0.0};
  const geometry::Pose2D start{0.5, -0.5, 0.1};
  LandmarkEkf ekf(options, start, diag(1.0, 1.0, 0.1));
  LandmarkEkf dead_reckoning(options, start, diag(1.0, 1.0, 0.1));
  Outcome out;
  const int steps = 600;
  for (int k = 0; k < steps; ++k) {
    const double t = k * dt;
    const double v = 1.0 + 0.3 * std::sin(0.05 * t);
    const double steer = 0.25 * std::sin(0.1 * t);
    for (int sub = 0; sub < 20; ++sub) {
      truth = tricycle_step(truth, v, steer, options.wheelbase_m, dt / 20);
    }
    const double v_measured = v + options.speed_sigma_mps * unit(rng);
    const double steer_measured = steer + options.steer_sigma_rad * unit(rng);
    EXPECT_TRUE(ekf.predict(v_measured, steer_measured, dt).applied());
    dead_reckoning.predict(v_measured, steer_measured, dt);
    std::vector<RangeBearingObservation> observations;
    for (const auto& l : landmarks) {
      const double range = std::hypot(l.x - truth.x, l.y - truth.y);
      const double bearing = std::atan2(l.y - truth.y, l.x - truth.x) - truth.theta;
      observations.push_back(
          {l, range + options.range_sigma_m * unit(rng),
           geometry::wrap_angle(bearing + options.bearing_sigma_rad * unit(rng))});
    }
    EXPECT_TRUE(ekf.update(observations).applied());
    const Eigen::Vector3d e(truth.x - ekf.pose().x, truth.y - ekf.pose().y,
                            geometry::wrap_angle(truth.theta - ekf.pose().theta));
    const double nees = e.dot(ekf.covariance().ldlt().solve(e));
    if (nees_per_step) nees_per_step->push_back(nees);
    if (k >= 50) out.mean_nees += nees / (steps - 50);
    out.final_error_m = e.head<2>().norm();
    out.rmse_m += e.head<2>().squaredNorm() / steps;
    out.final_heading_error_rad = std::abs(e(2));
  }
  out.rmse_m = std::sqrt(out.rmse_m);
  out.dead_reckoning_error_m =
      std::hypot(truth.x - dead_reckoning.pose().x, truth.y - dead_reckoning.pose().y);
  return out;
}

TEST(LandmarkEkf, ConvergesWithTwoLandmarks) {
  double nees = 0.0;
  const int runs = 10;
  for (int seed = 1; seed <= runs; ++seed) {
    const Outcome o = simulate({{10.0, 10.0}, {-5.0, 15.0}}, static_cast<unsigned>(seed));
    EXPECT_LT(o.final_error_m, 0.3) << seed;
    EXPECT_LT(o.final_heading_error_rad, 0.05) << seed;
    EXPECT_GT(o.dead_reckoning_error_m, 3.0 * o.final_error_m) << seed;
    nees += o.mean_nees / runs;
  }
  std::printf("LandmarkEkf mean NEES (2 landmarks, %d runs): %.2f\n", runs, nees);
  EXPECT_LT(nees, 6.0);
  EXPECT_GT(nees, 1.0);
}

TEST(LandmarkEkf, MidpointIntegrationIsConsistent) {
  LandmarkEkfOptions options;
  options.integration = TricycleIntegration::kMidpoint;
  double nees = 0.0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    nees += simulate({{10.0, 10.0}, {-5.0, 15.0}}, seed, options).mean_nees / 10;
  }
  std::printf("LandmarkEkf mean NEES with midpoint steps: %.2f\n", nees);
  EXPECT_LT(nees, 3.6);
  EXPECT_GT(nees, 2.2);
}

// The consistency test of Bar-Shalom et al. (Estimation with Applications to Tracking and
// Navigation, 5.4.2): over N Monte Carlo runs the average NEES at each step is chi-square with
// 3N degrees of freedom divided by N; its two-sided 95 % interval for N = 100 is [2.54, 3.50]
// (chi2(300) 2.5 % and 97.5 % points 253.9 and 349.9). A consistent filter has about 95 % of
// the steps inside it.
TEST(LandmarkEkf, NeesStaysInsideIts95PercentBoundsOver100Runs) {
  LandmarkEkfOptions options;
  options.integration = TricycleIntegration::kMidpoint;
  const int runs = 100;
  std::vector<double> average;
  for (unsigned seed = 1; seed <= runs; ++seed) {
    std::vector<double> nees;
    simulate({{10.0, 10.0}, {-5.0, 15.0}}, seed, options, &nees);
    if (average.empty()) average.assign(nees.size(), 0.0);
    for (std::size_t k = 0; k < nees.size(); ++k) average[k] += nees[k] / runs;
  }
  int inside = 0;
  int counted = 0;
  // The first steps carry the initial error of the 1 m prior, which is not what is tested.
  for (std::size_t k = 20; k < average.size(); ++k) {
    ++counted;
    if (average[k] >= 2.54 && average[k] <= 3.50) ++inside;
  }
  const double fraction = static_cast<double>(inside) / counted;
  std::printf("LandmarkEkf: %.1f %% of steps inside the 95 %% NEES bounds (100 runs)\n",
              100.0 * fraction);
  EXPECT_GE(fraction, 0.90);
}

TEST(LandmarkEkf, MoreLandmarksHelp) {
  double two = 0.0;
  double four = 0.0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    two += simulate({{10.0, 10.0}, {-5.0, 15.0}}, seed).rmse_m;
    four += simulate({{10.0, 10.0}, {-5.0, 15.0}, {20.0, -5.0}, {0.0, -10.0}}, seed).rmse_m;
  }
  EXPECT_LT(four, two);
}

TEST(LandmarkEkf, BearingInnovationWrapsAroundPi) {
  LandmarkEkf ekf({}, {0.0, 0.0, 0.0}, diag(0.01, 0.01, 0.01));
  // Landmark dead astern at 5 m, seen at -pi + 0.01 (i.e. pi + 0.01).
  ASSERT_TRUE(ekf.update({{{-5.0, 0.0}, 5.0, -kPi + 0.01}}).applied());
  EXPECT_LT(ekf.pose().theta, 0.0);
  EXPECT_GT(ekf.pose().theta, -0.011);
}

TEST(LandmarkEkf, BadInputsAreRejectedAndChangeNothing) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  LandmarkEkf ekf({}, {1.0, 1.0, 0.2}, diag(0.1, 0.1, 0.1));
  const auto pose = ekf.pose();
  const Eigen::Matrix3d cov = ekf.covariance();
  EXPECT_EQ(ekf.predict(nan, 0.0, 0.1).status, UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.predict(1.0, kPi / 2, 0.1).status, UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.predict(1.0, 0.0, -0.1).status, UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.update({}).status, UpdateStatus::kNoMatch);
  EXPECT_EQ(ekf.update({{{5.0, 5.0}, nan, 0.1}}).status, UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.update({{{1.0, 1.0}, 1.0, 0.1}}).status, UpdateStatus::kNumericalFailure);
  EXPECT_EQ(ekf.set_pose({nan, 0.0, 0.0}, cov).status, UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.pose(), pose);
  EXPECT_EQ(ekf.covariance(), cov);
}

}  // namespace
}  // namespace mobot::estimation
