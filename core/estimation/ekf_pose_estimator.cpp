#include "core/estimation/ekf_pose_estimator.h"

namespace mobot::estimation {

EkfPoseEstimator::EkfPoseEstimator(EkfPoseEstimatorOptions options)
    : options_(std::move(options)), ekf_(options_.filter), line_extractor_(options_.lines) {}

void EkfPoseEstimator::reset(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance) {
  ekf_.set_pose(pose, covariance);
}

void EkfPoseEstimator::update(const EstimatorInputs& inputs) {
  if (inputs.travel) ekf_.predict(inputs.travel->right_m, inputs.travel->left_m, inputs.track_m);
  // Lines first, then the compass: the order R1 reads its sensors in, which the reference results
  // were reproduced with.
  if (inputs.scan && options_.fuse_lines) fuse_scan(*inputs.scan);
  if (inputs.compass && options_.fuse_compass) {
    if (!ekf_.update_compass(inputs.compass->heading_rad).applied()) ++counters_.rejected_updates;
  }
  if (inputs.bearings && options_.fuse_bearing) {
    for (const auto& bearing : inputs.bearings->bearings) {
      if (!ekf_.update_bearing(bearing.bearing_rad, bearing.landmark_in_map).applied()) {
        ++counters_.rejected_updates;
      }
    }
  }
}

void EkfPoseEstimator::fuse_scan(const msgs::LaserScan& scan) {
  if (!map_ || map_->wall_lines.empty()) return;
  const auto report =
      ekf_.update_lines(line_extractor_.extract(scan), scan.sensor_in_base, map_->wall_lines);
  ++counters_.scan_updates;
  counters_.features_matched += report.matches.size();
  if (!report.update.applied() && !report.matches.empty()) ++counters_.rejected_updates;
}

std::string EkfPoseEstimator::method() const {
  std::string fused;
  if (options_.fuse_compass) fused += "+compass";
  if (options_.fuse_lines) fused += "+lines";
  if (options_.fuse_bearing) fused += "+bearing";
  if (fused.empty()) return options_.name;
  return options_.name + "(odometry" + fused + ")";
}

}  // namespace mobot::estimation
