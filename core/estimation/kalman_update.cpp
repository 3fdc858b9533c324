#include "core/estimation/kalman_update.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <numbers>

namespace mobot::estimation {

std::optional<KalmanCorrection> kalman_update(const Eigen::Matrix3d& covariance,
                                              const MeasurementJacobian& h,
                                              const Eigen::MatrixXd& noise,
                                              const Eigen::VectorXd& innovation) {
  const Eigen::MatrixXd s = h * covariance * h.transpose() + noise;
  const Eigen::LLT<Eigen::MatrixXd> llt(s);
  if (llt.info() != Eigen::Success) return std::nullopt;
  // K = P H^T S^-1, computed as (S^-1 H P)^T since S and P are symmetric.
  const Eigen::Matrix<double, 3, Eigen::Dynamic> gain = llt.solve(h * covariance).transpose();
  const Eigen::Matrix3d i_kh = Eigen::Matrix3d::Identity() - gain * h;
  KalmanCorrection out;
  out.state_delta = gain * innovation;
  out.covariance = i_kh * covariance * i_kh.transpose() + gain * noise * gain.transpose();
  out.covariance = 0.5 * (out.covariance + out.covariance.transpose()).eval();
  out.nis = innovation.dot(llt.solve(innovation));
  if (!out.state_delta.allFinite() || !out.covariance.allFinite() || !std::isfinite(out.nis)) {
    return std::nullopt;
  }
  return out;
}

std::optional<double> normalized_innovation_squared(const Eigen::Matrix3d& covariance,
                                                    const MeasurementJacobian& h,
                                                    const Eigen::MatrixXd& noise,
                                                    const Eigen::VectorXd& innovation) {
  const Eigen::MatrixXd s = h * covariance * h.transpose() + noise;
  const Eigen::LLT<Eigen::MatrixXd> llt(s);
  if (llt.info() != Eigen::Success) return std::nullopt;
  return innovation.dot(llt.solve(innovation));
}

std::optional<PoseEstimate> initial_estimate(const geometry::Pose2D& pose,
                                             const Eigen::Matrix3d& covariance) {
  if (!geometry::is_finite(pose) || !covariance.allFinite() ||
      (covariance.diagonal().array() < 0.0).any()) {
    return std::nullopt;
  }
  // wrap_angle is not exact for angles already in range; leave those bit for bit.
  const bool in_range = pose.theta > -std::numbers::pi && pose.theta <= std::numbers::pi;
  return PoseEstimate{{pose.x, pose.y, in_range ? pose.theta : geometry::wrap_angle(pose.theta)},
                      0.5 * (covariance + covariance.transpose())};
}

}  // namespace mobot::estimation
