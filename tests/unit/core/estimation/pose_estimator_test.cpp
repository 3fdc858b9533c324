#include "core/estimation/pose_estimator.h"

#include <gtest/gtest.h>

#include <limits>

#include "core/estimation/ekf_pose_estimator.h"

namespace mobot::estimation {
namespace {

Eigen::Matrix3d diag(double a, double b, double c) { return Eigen::Vector3d(a, b, c).asDiagonal(); }

TEST(PoseEstimator, TheDefaultConvergenceRuleReadsTheCovariance) {
  EXPECT_TRUE(covariance_converged(diag(0.14 * 0.14, 0.14 * 0.14, 0.09 * 0.09)));
  EXPECT_FALSE(covariance_converged(diag(0.16 * 0.16, 0.01, 0.001)));
  EXPECT_FALSE(covariance_converged(diag(0.01, 0.01, 0.11 * 0.11)));
  // Long along a diagonal: each axis alone is under 0.15 m, the ellipse is not.
  Eigen::Matrix3d diagonal = diag(0.018, 0.018, 0.001);
  diagonal(0, 1) = diagonal(1, 0) = 0.017;
  EXPECT_FALSE(covariance_converged(diagonal));
  EXPECT_FALSE(covariance_converged(diag(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0)));
}

TEST(PoseEstimator, SingleHypothesisEstimatorsKeepTheDefaults) {
  EkfPoseEstimator ekf({});
  ekf.reset({1.0, 2.0, 0.3}, diag(1e-4, 1e-4, 1e-4));
  EXPECT_TRUE(ekf.converged());
  ekf.reset({1.0, 2.0, 0.3}, diag(1.0, 1.0, 1.0));
  EXPECT_FALSE(ekf.converged());
  EXPECT_FALSE(ekf.start_global_localization());
  EXPECT_TRUE(ekf.particles(100).empty());
}

}  // namespace
}  // namespace mobot::estimation
