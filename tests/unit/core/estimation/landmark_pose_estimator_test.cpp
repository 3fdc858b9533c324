#include "core/estimation/landmark_pose_estimator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/kinematics/tricycle.h"

namespace mobot::estimation {
namespace {

// A type 2 tricycle driving a slow S through four beacons; its rear wheels (1.0 m apart) report
// their travel every 20 ms with 2 % noise, and the scanner ranges the beacons every 100 ms.
struct Scenario {
  double final_error_m = 0.0;
  double dead_reckoning_error_m = 0.0;
  double final_sigma_m = 0.0;
};

Scenario run(bool with_ranges, unsigned seed) {
  const double track = 1.0;
  const kinematics::TricycleGeometry geometry;
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  const std::vector<geometry::Point2D> beacons{{0, 20}, {30, 20}, {30, -5}, {0, -5}};
  LandmarkPoseEstimatorOptions options;
  options.filter.integration = TricycleIntegration::kMidpoint;
  LandmarkPoseEstimator estimator(options);
  estimator.reset({0, 0, 0}, Eigen::Matrix3d(Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal()));
  geometry::Pose2D truth;
  geometry::Pose2D dead_reckoning;
  for (int k = 1; k <= 3000; ++k) {  // 60 s
    const double t = k * 0.02;
    const kinematics::TricycleInput input{1.0, 0.3 * std::sin(0.1 * t)};
    const geometry::Pose2D before = truth;
    truth = kinematics::integrate_tricycle_rk4(geometry, truth, [&](double) { return input; }, t,
                                               0.02, 0.005);
    const msgs::Twist body = kinematics::tricycle_body_velocity(geometry, input);
    const double ds = body.linear_mps * 0.02;
    const double dth = geometry::wrap_angle(truth.theta - before.theta);
    WheelTravel travel{(ds - dth * track / 2) * (1 + 0.02 * unit(rng)),
                       (ds + dth * track / 2) * (1 + 0.02 * unit(rng))};
    dead_reckoning.theta += (travel.right_m - travel.left_m) / track;
    dead_reckoning.x += (travel.right_m + travel.left_m) / 2 * std::cos(dead_reckoning.theta);
    dead_reckoning.y += (travel.right_m + travel.left_m) / 2 * std::sin(dead_reckoning.theta);
    EstimatorInputs inputs;
    inputs.stamp_s = t;
    inputs.travel = &travel;
    inputs.track_m = track;
    msgs::LandmarkBearings seen;
    if (k % 5 == 0) {
      for (const auto& b : beacons) {
        msgs::LandmarkBearing sighting{"b", b,
                                       geometry::wrap_angle(std::atan2(b.y - truth.y, b.x - truth.x) -
                                                            truth.theta + 0.035 * unit(rng)),
                                       std::nullopt};
        if (with_ranges) sighting.range_m = std::hypot(b.x - truth.x, b.y - truth.y) + 0.1 * unit(rng);
        seen.bearings.push_back(sighting);
      }
      inputs.bearings = &seen;
    }
    estimator.update(inputs);
  }
  const geometry::Pose2D estimate = estimator.pose();
  return {std::hypot(estimate.x - truth.x, estimate.y - truth.y),
          std::hypot(dead_reckoning.x - truth.x, dead_reckoning.y - truth.y),
          std::sqrt(estimator.covariance()(0, 0) + estimator.covariance()(1, 1))};
}

TEST(LandmarkPoseEstimator, RangedBeaconsHoldThePoseWhereOdometryDrifts) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const Scenario s = run(true, seed);
    EXPECT_LT(s.final_error_m, 0.3) << seed;
    EXPECT_LT(s.final_sigma_m, 0.3) << seed;
  }
}

TEST(LandmarkPoseEstimator, BearingsWithoutRangeAreNotFused) {
  const Scenario s = run(false, 1);
  // Prediction only: E3's s_v = 0.1 m/s over 60 s lets the covariance grow to metres.
  EXPECT_GT(s.final_sigma_m, 1.0);
}

TEST(LandmarkPoseEstimator, NamesItselfAndResets) {
  LandmarkPoseEstimator estimator;
  EXPECT_EQ(estimator.name(), "landmark_ekf");
  estimator.reset({1, 2, 0.5}, Eigen::Matrix3d::Identity() * 0.01);
  EXPECT_DOUBLE_EQ(estimator.pose().x, 1.0);
  EXPECT_DOUBLE_EQ(estimator.covariance()(0, 0), 0.01);
}

}  // namespace
}  // namespace mobot::estimation
