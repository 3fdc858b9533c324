#include "server/mapping/slam_estimator.h"

#include <cmath>

#include "core/kinematics/diff_drive.h"

namespace mobot::server {

SlamEstimator::SlamEstimator(std::shared_ptr<SlamWorker> worker, const geometry::Pose2D& odom_start)
    : worker_(std::move(worker)), odom_pose_(odom_start) {}

void SlamEstimator::update(const estimation::EstimatorInputs& inputs) {
  if (inputs.travel != nullptr && inputs.track_m > 0.0 && std::isfinite(inputs.travel->left_m) &&
      std::isfinite(inputs.travel->right_m)) {
    odom_pose_ = kinematics::integrate_wheel_travel(odom_pose_, inputs.travel->left_m,
                                                    inputs.travel->right_m, inputs.track_m);
  }
  if (inputs.scan != nullptr) {
    worker_->submit(*inputs.scan, odom_pose_);
    ++counters_.scan_updates;
  }
}

geometry::Pose2D SlamEstimator::pose() const {
  return geometry::compose(worker_->map_from_odom(), odom_pose_);
}

Eigen::Matrix3d SlamEstimator::covariance() const {
  // The scan matcher's typical spread on a 0.05 m grid (2 cm, 1 deg); the graph does not
  // marginalise a covariance for the newest node.
  return Eigen::Vector3d(4e-4, 4e-4, 3e-4).asDiagonal();
}

}  // namespace mobot::server
