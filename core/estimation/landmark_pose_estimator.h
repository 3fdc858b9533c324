#pragma once

#include <string>

#include "core/estimation/landmark_ekf.h"
#include "core/estimation/pose_estimator.h"

namespace mobot::estimation {

struct LandmarkPoseEstimatorOptions {
  LandmarkEkfOptions filter;
  // E3 predicts every dt = 0.1 s; its process noise (s_v, s_alpha through W, which scales with
  // dt) is tuned for that step, so the control loop's 20 ms travels are summed into it.
  double predict_period_s = 0.1;
};

// The range-bearing landmark EKF of docs/algorithms.md E3 as a PoseEstimator for the tricycles:
// the rear wheels' travel over each prediction step gives the reference point's speed v and the
// steering angle alpha = atan(d dtheta / ds) (both tricycle types move their rear-axle centre so),
// and every landmark the beacon scanner ranged fuses as one range and one bearing row.
// Landmark sightings without a range (an omni camera's bearings) are ignored.
class LandmarkPoseEstimator final : public PoseEstimator {
 public:
  explicit LandmarkPoseEstimator(LandmarkPoseEstimatorOptions options = {});

  std::string_view name() const override { return "landmark_ekf"; }
  std::string method() const override { return "landmark_ekf (odometry + range-bearing landmarks)"; }
  void reset(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance) override;
  void set_map(std::shared_ptr<const MapModel>) override {}
  void update(const EstimatorInputs& inputs) override;
  // The filter's pose moved on by the travel summed since its last prediction.
  geometry::Pose2D pose() const override;
  Eigen::Matrix3d covariance() const override { return ekf_.covariance(); }
  EstimatorCounters counters() const override { return counters_; }

 private:
  // Predicts over the time since the last prediction with the travel summed since.
  void predict_pending(double now_s);

  LandmarkPoseEstimatorOptions options_;
  LandmarkEkf ekf_;
  EstimatorCounters counters_;
  // Travel since the last prediction: arc length and heading change of the rear-axle centre,
  // and its displacement in the frame of the filter's pose.
  double pending_ds_m_ = 0.0;
  double pending_dtheta_rad_ = 0.0;
  geometry::Pose2D pending_delta_;
  double pending_since_s_ = 0.0;
  bool started_ = false;
};

}  // namespace mobot::estimation
