#include "core/estimation/landmark_pose_estimator.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace mobot::estimation {
namespace {

// Below this travel over a prediction step the steering angle cannot be told from the wheels.
constexpr double kMinTravelForSteering_m = 1e-4;
constexpr double kMaxSteer_rad = 1.4;

}  // namespace

LandmarkPoseEstimator::LandmarkPoseEstimator(LandmarkPoseEstimatorOptions options)
    : options_(options), ekf_(options_.filter) {}

void LandmarkPoseEstimator::reset(const geometry::Pose2D& pose,
                                  const Eigen::Matrix3d& covariance) {
  ekf_.set_pose(pose, covariance);
  pending_ds_m_ = pending_dtheta_rad_ = 0.0;
  pending_delta_ = {};
  started_ = false;
}

geometry::Pose2D LandmarkPoseEstimator::pose() const {
  const geometry::Pose2D moved = geometry::compose(ekf_.pose(), pending_delta_);
  return {moved.x, moved.y, geometry::wrap_angle(moved.theta)};
}

void LandmarkPoseEstimator::update(const EstimatorInputs& inputs) {
  if (!started_) {
    pending_since_s_ = inputs.stamp_s;
    started_ = true;
  }
  if (inputs.travel && inputs.track_m > 0.0) {
    const double ds_m = (inputs.travel->right_m + inputs.travel->left_m) / 2.0;
    const double dtheta_rad = (inputs.travel->right_m - inputs.travel->left_m) / inputs.track_m;
    if (std::isfinite(ds_m) && std::isfinite(dtheta_rad)) {
      // Midpoint step in the frame of the filter's pose, as E1's odometry integrates.
      const double heading = pending_delta_.theta + dtheta_rad / 2.0;
      pending_delta_.x += ds_m * std::cos(heading);
      pending_delta_.y += ds_m * std::sin(heading);
      pending_delta_.theta += dtheta_rad;
      pending_ds_m_ += ds_m;
      pending_dtheta_rad_ += dtheta_rad;
    }
  }
  if (inputs.stamp_s - pending_since_s_ >= options_.predict_period_s) {
    predict_pending(inputs.stamp_s);
  }
  if (!inputs.bearings) return;
  std::vector<RangeBearingObservation> observations;
  for (const msgs::LandmarkBearing& seen : inputs.bearings->bearings) {
    if (seen.range_m) observations.push_back({seen.landmark_in_map, *seen.range_m, seen.bearing_rad});
  }
  if (observations.empty()) return;
  // The sighting is of now: bring the filter up to now before correcting it.
  predict_pending(inputs.stamp_s);
  const UpdateReport report = ekf_.update(observations);
  if (report.applied()) {
    ++counters_.scan_updates;
    counters_.features_matched += observations.size();
  } else {
    ++counters_.rejected_updates;
  }
}

void LandmarkPoseEstimator::predict_pending(double now_s) {
  const double dt_s = now_s - pending_since_s_;
  if (!(dt_s > 0.0)) return;
  const double speed_mps = pending_ds_m_ / dt_s;
  // A wheel slip can make the rear axle turn sharper than any steering can; the model's W needs
  // cos(alpha) well away from 0.
  const double steer_rad =
      std::abs(pending_ds_m_) > kMinTravelForSteering_m
          ? std::clamp(std::atan(options_.filter.wheelbase_m * pending_dtheta_rad_ / pending_ds_m_),
                       -kMaxSteer_rad, kMaxSteer_rad)
          : 0.0;
  // The filter integrates the inputs itself (E3's model); the summed travel only supplies them.
  ekf_.predict(speed_mps, steer_rad, dt_s);
  pending_ds_m_ = pending_dtheta_rad_ = 0.0;
  pending_delta_ = {};
  pending_since_s_ = now_s;
}

}  // namespace mobot::estimation
