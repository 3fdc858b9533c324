#include "server/localization.h"

#include "api/prometheus_text.h"

namespace mobot::server {

Localization::Localization(const LocalizationSection& config,
                           const estimation::OdometryParams& odometry,
                           const geometry::Pose2D& start)
    : config_(config), odometry_(odometry, start), ekf_({}, start) {}

void Localization::reset(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance) {
  odometry_ = estimation::WheelOdometry(odometry_.params(), pose);
  ekf_.set_pose(pose, covariance);
}

void Localization::set_pose(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance) {
  ekf_.set_pose(pose, covariance);
}

void Localization::on_encoders(const msgs::WheelEncoders& encoders) {
  odometry_.update(encoders);
  const estimation::WheelTravel& travel = odometry_.last_travel();
  ekf_.predict(travel.right_m, travel.left_m, odometry_.params().track_m);
}

void Localization::on_compass(const msgs::CompassReading& reading) {
  if (config_.method != "ekf" || !config_.fuse_compass) return;
  if (!ekf_.update_compass(reading.heading_rad).applied()) ++rejected_updates_;
}

void Localization::on_scan(const msgs::LaserScan& scan) {
  if (config_.method != "ekf" || !config_.fuse_lines || map_lines_.empty()) return;
  const auto report =
      ekf_.update_lines(line_extractor_.extract(scan), scan.sensor_in_base, map_lines_);
  ++line_updates_;
  lines_matched_ += report.matches.size();
  if (!report.update.applied() && !report.matches.empty()) ++rejected_updates_;
}

void Localization::on_bearings(const msgs::LandmarkBearings& bearings) {
  if (config_.method != "ekf" || !config_.fuse_bearing) return;
  for (const auto& bearing : bearings.bearings) {
    if (!ekf_.update_bearing(bearing.bearing_rad, bearing.landmark_in_map).applied()) {
      ++rejected_updates_;
    }
  }
}

std::string Localization::method() const {
  if (config_.method != "ekf") return "odometry";
  std::string fused;
  if (config_.fuse_compass) fused += "+compass";
  if (config_.fuse_lines) fused += "+lines";
  if (config_.fuse_bearing) fused += "+bearing";
  return fused.empty() ? "ekf" : "ekf(odometry" + fused + ")";
}

std::string Localization::metrics_text() const {
  std::string out;
  api::append_metric(out, "mobot_localization_line_updates_total", "counter",
                     "Scans fused as line features.", static_cast<double>(line_updates_));
  api::append_metric(out, "mobot_localization_lines_matched_total", "counter",
                     "Scan lines matched to map lines.", static_cast<double>(lines_matched_));
  api::append_metric(out, "mobot_localization_rejected_updates_total", "counter",
                     "EKF updates refused (gate, NaN).", static_cast<double>(rejected_updates_));
  return out;
}

}  // namespace mobot::server
