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

// W (the input Jacobian of E2) and A against finite differences of the E1 step, at headings around
// the +-pi wrap as well.
TEST(OdometryCovariance, InputJacobianMatchesFiniteDifferences) {
  const double track_m = 0.6;
  const double h = 1e-7;
  for (const double theta : {0.7, 3.14159, -3.14159, -1.2}) {
    const geometry::Pose2D pose{1.0, -2.0, theta};
    const double left_m = 0.04;
    const double right_m = 0.09;
    const OdometryJacobians j = odometry_jacobians(pose, left_m, right_m, track_m);
    const auto base = kinematics::integrate_wheel_travel(pose, left_m, right_m, track_m);
    const auto by_right = kinematics::integrate_wheel_travel(pose, left_m, right_m + h, track_m);
    const auto by_left = kinematics::integrate_wheel_travel(pose, left_m + h, right_m, track_m);
    EXPECT_NEAR(j.w(0, 0), (by_right.x - base.x) / h, 1e-6);
    EXPECT_NEAR(j.w(1, 0), (by_right.y - base.y) / h, 1e-6);
    EXPECT_NEAR(j.w(2, 0), geometry::wrap_angle(by_right.theta - base.theta) / h, 1e-6);
    EXPECT_NEAR(j.w(0, 1), (by_left.x - base.x) / h, 1e-6);
    EXPECT_NEAR(j.w(1, 1), (by_left.y - base.y) / h, 1e-6);
    EXPECT_NEAR(j.w(2, 1), geometry::wrap_angle(by_left.theta - base.theta) / h, 1e-6);
    // and A, across the wrap: only the heading column is not the identity.
    geometry::Pose2D turned = pose;
    turned.theta += h;
    const auto by_heading = kinematics::integrate_wheel_travel(turned, left_m, right_m, track_m);
    EXPECT_NEAR(j.a(0, 2), (by_heading.x - base.x) / h, 1e-6);
    EXPECT_NEAR(j.a(1, 2), (by_heading.y - base.y) / h, 1e-6);
    EXPECT_NEAR(j.a(2, 2), geometry::wrap_angle(by_heading.theta - base.theta) / h, 1e-6);
  }
}

}  // namespace
}  // namespace mobot::estimation
