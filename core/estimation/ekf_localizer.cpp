#include "core/estimation/ekf_localizer.h"

#include <cmath>
#include <numbers>

#include "core/estimation/kalman_update.h"
#include "core/estimation/landmark_measurement_model.h"
#include "core/kinematics/diff_drive.h"

namespace mobot::estimation {
namespace {

bool all_valid(const std::vector<perception::LineSegment>& lines) {
  for (const perception::LineSegment& line : lines) {
    if (!perception::is_valid(line)) return false;
  }
  return true;
}

}  // namespace

EkfLocalizer::EkfLocalizer(const EkfLocalizerOptions& options, const geometry::Pose2D& pose,
                           const Eigen::Matrix3d& covariance)
    : options_(options), pose_(pose), covariance_(Eigen::Matrix3d::Zero()) {
  set_pose(pose, covariance);
}

UpdateReport EkfLocalizer::set_pose(const geometry::Pose2D& pose,
                                    const Eigen::Matrix3d& covariance) {
  const auto estimate = initial_estimate(pose, covariance);
  if (!estimate) return UpdateReport::rejected(UpdateStatus::kRejectedNonFinite);
  pose_ = estimate->pose;
  covariance_ = estimate->covariance;
  return {};
}

UpdateReport EkfLocalizer::predict(double ds_right_m, double ds_left_m, double track_m) {
  if (!std::isfinite(ds_right_m) || !std::isfinite(ds_left_m) || !std::isfinite(track_m) ||
      !(track_m > 0.0)) {
    return UpdateReport::rejected(UpdateStatus::kRejectedNonFinite);
  }
  Eigen::Matrix3d next = propagate_odometry_covariance(covariance_, pose_, ds_left_m, ds_right_m,
                                                       track_m, options_.wheel_noise);
  next = 0.5 * (next + next.transpose()).eval();
  if (!next.allFinite()) return UpdateReport::rejected(UpdateStatus::kNumericalFailure);
  pose_ = kinematics::integrate_wheel_travel(pose_, ds_left_m, ds_right_m, track_m);
  covariance_ = next;
  return {};
}

UpdateReport EkfLocalizer::update_compass(double heading_rad) {
  if (!std::isfinite(heading_rad)) return UpdateReport::rejected(UpdateStatus::kRejectedNonFinite);
  MeasurementJacobian h(1, 3);
  h << 0.0, 0.0, 1.0;
  Eigen::MatrixXd noise(1, 1);
  noise(0, 0) = options_.compass_var_rad2;
  Eigen::VectorXd innovation(1);
  innovation(0) = geometry::wrap_angle(heading_rad - pose_.theta);
  return correct(h, noise, innovation, options_.compass_gate_chi2);
}

UpdateReport EkfLocalizer::update_bearing(double bearing_rad,
                                          const geometry::Point2D& landmark_in_map) {
  if (!std::isfinite(bearing_rad) || !std::isfinite(landmark_in_map.x) ||
      !std::isfinite(landmark_in_map.y)) {
    return UpdateReport::rejected(UpdateStatus::kRejectedNonFinite);
  }
  const auto prediction = predict_bearing(pose_, landmark_in_map);
  if (!prediction) return UpdateReport::rejected(UpdateStatus::kNumericalFailure);
  MeasurementJacobian h(1, 3);
  h.row(0) = prediction->h;
  Eigen::MatrixXd noise(1, 1);
  noise(0, 0) = options_.bearing_var_rad2;
  Eigen::VectorXd innovation(1);
  innovation(0) = geometry::wrap_angle(bearing_rad - prediction->z);
  return correct(h, noise, innovation, options_.bearing_gate_chi2);
}

LineUpdateReport EkfLocalizer::update_lines(
    const std::vector<perception::LineSegment>& observed_in_sensor,
    const geometry::Pose2D& sensor_in_base, const std::vector<perception::LineSegment>& map_lines) {
  LineUpdateReport report;
  if (!geometry::is_finite(sensor_in_base) || !all_valid(observed_in_sensor) ||
      !all_valid(map_lines)) {
    report.update = UpdateReport::rejected(UpdateStatus::kRejectedNonFinite);
    return report;
  }
  std::vector<perception::LineSegment> observed_in_base;
  observed_in_base.reserve(observed_in_sensor.size());
  for (const perception::LineSegment& line : observed_in_sensor) {
    observed_in_base.push_back(perception::transform_line(sensor_in_base, line));
  }
  report.matches =
      match_lines(pose_, covariance_, observed_in_base, map_lines, options_.line_matching);
  if (report.matches.empty()) {
    report.update = UpdateReport::rejected(UpdateStatus::kNoMatch);
    return report;
  }
  const auto rows = static_cast<Eigen::Index>(2 * report.matches.size());
  MeasurementJacobian h(rows, 3);
  Eigen::MatrixXd noise = Eigen::MatrixXd::Zero(rows, rows);
  Eigen::VectorXd innovation(rows);
  for (std::size_t k = 0; k < report.matches.size(); ++k) {
    const LineMatch& match = report.matches[k];
    const auto row = static_cast<Eigen::Index>(2 * k);
    h.middleRows<2>(row) = match.prediction.h;
    noise.block<2, 2>(row, row) = match.noise;
    innovation.segment<2>(row) = match.innovation;
  }
  report.update = correct(h, noise, innovation, 0.0);
  return report;
}

UpdateReport EkfLocalizer::correct(const MeasurementJacobian& h, const Eigen::MatrixXd& noise,
                                   const Eigen::VectorXd& innovation, double gate_chi2) {
  UpdateReport report;
  report.rows_used = static_cast<int>(innovation.size());
  if (gate_chi2 > 0.0) {
    const auto nis = normalized_innovation_squared(covariance_, h, noise, innovation);
    if (!nis) return UpdateReport::rejected(UpdateStatus::kNumericalFailure);
    if (*nis > gate_chi2) {
      report.status = UpdateStatus::kRejectedOutlier;
      report.nis = *nis;
      report.rows_used = 0;
      return report;
    }
  }
  const auto correction = kalman_update(covariance_, h, noise, innovation);
  if (!correction) return UpdateReport::rejected(UpdateStatus::kNumericalFailure);
  pose_.x += correction->state_delta(0);
  pose_.y += correction->state_delta(1);
  pose_.theta = geometry::wrap_angle(pose_.theta + correction->state_delta(2));
  covariance_ = correction->covariance;
  report.nis = correction->nis;
  return report;
}

}  // namespace mobot::estimation
