#include "core/estimation/odometry_covariance.h"

#include <gtest/gtest.h>

#include "core/kinematics/diff_drive.h"

namespace mobot::estimation {
namespace {

// The Jacobians A and W must match finite differences of the motion model (E1).
TEST(OdometryCovariance, JacobiansMatchFiniteDifferences) {
  const geometry::Pose2D pose{1.0, 2.0, 0.7};
  const double left_m = 0.05;
  const double right_m = 0.07;
  const double track_m = 0.6;
  // With P = e_i e_i^T and Q = 0, the result's column i is A e_i e_i^T A^T -> check via A e_i.
  const double h = 1e-6;
  for (int i = 0; i < 3; ++i) {
    Eigen::Matrix3d p = Eigen::Matrix3d::Zero();
    p(i, i) = 1.0;
    const Eigen::Matrix3d out =
        propagate_odometry_covariance(p, pose, left_m, right_m, track_m, {0.0, 0.0});
    geometry::Pose2D bumped = pose;
    (i == 0 ? bumped.x : i == 1 ? bumped.y : bumped.theta) += h;
    const auto base = kinematics::integrate_wheel_travel(pose, left_m, right_m, track_m);
    const auto moved = kinematics::integrate_wheel_travel(bumped, left_m, right_m, track_m);
    const Eigen::Vector3d column{(moved.x - base.x) / h, (moved.y - base.y) / h,
                                 (moved.theta - base.theta) / h};
    EXPECT_TRUE(out.isApprox(column * column.transpose(), 1e-5)) << "state " << i;
  }
}

TEST(OdometryCovariance, GrowsWithDistanceOnly) {
  const Eigen::Matrix3d zero = Eigen::Matrix3d::Zero();
  const auto still = propagate_odometry_covariance(zero, {}, 0.0, 0.0, 0.6, {});
  EXPECT_TRUE(still.isZero());
  const auto moved = propagate_odometry_covariance(zero, {}, 0.1, 0.1, 0.6, {});
  EXPECT_GT(moved(0, 0), 0.0);
  EXPECT_GT(moved(2, 2), 0.0);
}

}  // namespace
}  // namespace mobot::estimation
