#pragma once

#include <Eigen/Core>

#include "core/geometry/pose2d.h"

namespace mobot::estimation {

// The encoder noise model of docs/algorithms.md E2: each wheel's travel has variance proportional
// to its length, Q = diag(k_right |ds_R|, k_left |ds_L|).
struct WheelNoise {
  double k_right = 0.0003;
  double k_left = 0.0003;
};

// Jacobians of the E1 odometry step at the mid-step heading: A = d pose' / d pose and
// W = d pose' / d (ds_R, ds_L) (columns in that order), exactly as docs/algorithms.md E2 writes
// them.
struct OdometryJacobians {
  Eigen::Matrix3d a;
  Eigen::Matrix<double, 3, 2> w;
};

OdometryJacobians odometry_jacobians(const geometry::Pose2D& pose_before, double left_travel_m,
                                     double right_travel_m, double track_m);

// Propagates the pose covariance through one odometry step (the EKF prediction of E2 without a
// correction): P' = A P A^T + W Q W^T, A and W evaluated at the mid-step heading.
Eigen::Matrix3d propagate_odometry_covariance(const Eigen::Matrix3d& covariance,
                                              const geometry::Pose2D& pose_before,
                                              double left_travel_m, double right_travel_m,
                                              double track_m, const WheelNoise& noise);

}  // namespace mobot::estimation
