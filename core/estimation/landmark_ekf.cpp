#include "core/estimation/landmark_ekf.h"

#include <cmath>
#include <numbers>

#include "core/estimation/kalman_update.h"
#include "core/estimation/landmark_measurement_model.h"
#include "core/estimation/tricycle_motion_model.h"

namespace mobot::estimation {
namespace {

bool finite_observation(const RangeBearingObservation& o) {
  return std::isfinite(o.landmark_in_map.x) && std::isfinite(o.landmark_in_map.y) &&
         std::isfinite(o.range_m) && std::isfinite(o.bearing_rad);
}

}  // namespace

LandmarkEkf::LandmarkEkf(const LandmarkEkfOptions& options, const geometry::Pose2D& pose,
                         const Eigen::Matrix3d& covariance)
    : options_(options), pose_(pose), covariance_(Eigen::Matrix3d::Zero()) {
  set_pose(pose, covariance);
}

UpdateReport LandmarkEkf::set_pose(const geometry::Pose2D& pose,
                                   const Eigen::Matrix3d& covariance) {
  const auto estimate = initial_estimate(pose, covariance);
  if (!estimate) return UpdateReport::rejected(UpdateStatus::kRejectedNonFinite);
  pose_ = estimate->pose;
  covariance_ = estimate->covariance;
  return {};
}

UpdateReport LandmarkEkf::predict(double speed_mps, double steer_rad, double dt_s) {
  if (!std::isfinite(speed_mps) || !std::isfinite(steer_rad) || !std::isfinite(dt_s) ||
      dt_s < 0.0 || !(std::cos(steer_rad) > 1e-6) || !(options_.wheelbase_m > 0.0)) {
    return UpdateReport::rejected(UpdateStatus::kRejectedNonFinite);
  }
  const TricycleJacobians j = tricycle_jacobians(pose_, speed_mps, steer_rad, options_.wheelbase_m,
                                                 dt_s, options_.integration);
  Eigen::Matrix2d q = Eigen::Matrix2d::Zero();
  q(0, 0) = options_.speed_sigma_mps * options_.speed_sigma_mps;
  q(1, 1) = options_.steer_sigma_rad * options_.steer_sigma_rad;
  Eigen::Matrix3d next = j.a * covariance_ * j.a.transpose() + j.w * q * j.w.transpose();
  next = 0.5 * (next + next.transpose()).eval();
  if (!next.allFinite()) return UpdateReport::rejected(UpdateStatus::kNumericalFailure);
  pose_ =
      tricycle_step(pose_, speed_mps, steer_rad, options_.wheelbase_m, dt_s, options_.integration);
  covariance_ = next;
  return {};
}

UpdateReport LandmarkEkf::update(const std::vector<RangeBearingObservation>& observations) {
  if (observations.empty()) return UpdateReport::rejected(UpdateStatus::kNoMatch);
  for (const RangeBearingObservation& o : observations) {
    if (!finite_observation(o)) return UpdateReport::rejected(UpdateStatus::kRejectedNonFinite);
  }
  const auto rows = static_cast<Eigen::Index>(2 * observations.size());
  MeasurementJacobian h(rows, 3);
  Eigen::MatrixXd noise = Eigen::MatrixXd::Zero(rows, rows);
  Eigen::VectorXd innovation(rows);
  for (std::size_t k = 0; k < observations.size(); ++k) {
    const RangeBearingObservation& o = observations[k];
    const auto range = predict_range(pose_, o.landmark_in_map);
    const auto bearing = predict_bearing(pose_, o.landmark_in_map);
    if (!range || !bearing) return UpdateReport::rejected(UpdateStatus::kNumericalFailure);
    const auto row = static_cast<Eigen::Index>(2 * k);
    h.row(row) = range->h;
    h.row(row + 1) = bearing->h;
    noise(row, row) = options_.range_sigma_m * options_.range_sigma_m;
    noise(row + 1, row + 1) = options_.bearing_sigma_rad * options_.bearing_sigma_rad;
    innovation(row) = o.range_m - range->z;
    innovation(row + 1) = geometry::wrap_angle(o.bearing_rad - bearing->z);
  }
  const auto correction = kalman_update(covariance_, h, noise, innovation);
  if (!correction) return UpdateReport::rejected(UpdateStatus::kNumericalFailure);
  pose_.x += correction->state_delta(0);
  pose_.y += correction->state_delta(1);
  pose_.theta = geometry::wrap_angle(pose_.theta + correction->state_delta(2));
  covariance_ = correction->covariance;
  UpdateReport report;
  report.rows_used = static_cast<int>(rows);
  report.nis = correction->nis;
  return report;
}

}  // namespace mobot::estimation
