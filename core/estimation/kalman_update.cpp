#include "core/estimation/kalman_update.h"

#include <Eigen/Cholesky>
#include <cmath>

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

}  // namespace mobot::estimation
