#include "core/estimation/odometry_covariance.h"

#include <cmath>

namespace mobot::estimation {

OdometryJacobians odometry_jacobians(const geometry::Pose2D& pose_before, double left_travel_m,
                                     double right_travel_m, double track_m) {
  const double ds = (right_travel_m + left_travel_m) / 2.0;
  const double dtheta = (right_travel_m - left_travel_m) / track_m;
  const double heading = pose_before.theta + dtheta / 2.0;
  const double c = std::cos(heading);
  const double s = std::sin(heading);

  OdometryJacobians j;
  j.a = Eigen::Matrix3d::Identity();
  j.a(0, 2) = -ds * s;
  j.a(1, 2) = ds * c;
  // Columns: d/d(ds_R), d/d(ds_L).
  j.w << c / 2 - ds * s / (2 * track_m), c / 2 + ds * s / (2 * track_m),
      s / 2 + ds * c / (2 * track_m), s / 2 - ds * c / (2 * track_m), 1 / track_m, -1 / track_m;
  return j;
}

Eigen::Matrix3d propagate_odometry_covariance(const Eigen::Matrix3d& covariance,
                                              const geometry::Pose2D& pose_before,
                                              double left_travel_m, double right_travel_m,
                                              double track_m, const WheelNoise& noise) {
  const OdometryJacobians j =
      odometry_jacobians(pose_before, left_travel_m, right_travel_m, track_m);
  Eigen::Matrix2d q = Eigen::Matrix2d::Zero();
  q(0, 0) = noise.k_right * std::abs(right_travel_m);
  q(1, 1) = noise.k_left * std::abs(left_travel_m);
  return j.a * covariance * j.a.transpose() + j.w * q * j.w.transpose();
}

}  // namespace mobot::estimation
