#pragma once

#include <Eigen/Core>
#include <optional>

#include "core/geometry/pose2d.h"

namespace mobot::estimation {

// Measurement Jacobian and noise of a stacked update on a three-dimensional pose state.
using MeasurementJacobian = Eigen::Matrix<double, Eigen::Dynamic, 3>;

struct KalmanCorrection {
  Eigen::Vector3d state_delta;  // add to the state (then wrap the heading)
  Eigen::Matrix3d covariance;   // the corrected covariance, symmetric
  double nis = 0.0;             // nu^T S^-1 nu
};

// One EKF correction in Joseph form, P' = (I - K H) P (I - K H)^T + K R K^T, which stays
// symmetric positive semi-definite under rounding, unlike (I - K H) P. `innovation` must already
// have its angle rows wrapped. nullopt when S = H P H^T + R is not positive definite or the
// result is not finite.
std::optional<KalmanCorrection> kalman_update(const Eigen::Matrix3d& covariance,
                                              const MeasurementJacobian& h,
                                              const Eigen::MatrixXd& noise,
                                              const Eigen::VectorXd& innovation);

// nu^T S^-1 nu with S = H P H^T + R; nullopt when S is not positive definite.
std::optional<double> normalized_innovation_squared(const Eigen::Matrix3d& covariance,
                                                    const MeasurementJacobian& h,
                                                    const Eigen::MatrixXd& noise,
                                                    const Eigen::VectorXd& innovation);

struct PoseEstimate {
  geometry::Pose2D pose;
  Eigen::Matrix3d covariance;
};

// A pose and covariance to (re)start a pose EKF from, or nullopt when either is not finite or a
// variance is negative. The heading is wrapped (left bit for bit when already in range) and the
// covariance symmetrised.
std::optional<PoseEstimate> initial_estimate(const geometry::Pose2D& pose,
                                             const Eigen::Matrix3d& covariance);

}  // namespace mobot::estimation
