#pragma once

#include <memory>

#include "core/estimation/pose_estimator.h"
#include "server/mapping/slam_worker.h"

namespace mobot::server {

// The pose estimate while mapping: the SLAM's map -> odom correction (from its worker, as fresh as
// the last matched scan) composed with this estimator's own dead reckoning, so the pose moves at
// the control rate while the matcher works at the laser's pace.
class SlamEstimator final : public estimation::PoseEstimator {
 public:
  // `start` is where the robot is in the map frame when mapping starts.
  SlamEstimator(std::shared_ptr<SlamWorker> worker, const geometry::Pose2D& odom_start);

  std::string_view name() const override { return "slam"; }
  std::string method() const override { return "slam(laser+odometry)"; }

  // A mapping session keeps the frame it started in: a pose given by hand is not taken (the
  // mapping service refuses it before it gets here).
  void reset(const geometry::Pose2D&, const Eigen::Matrix3d&) override {}
  void set_map(std::shared_ptr<const estimation::MapModel>) override {}
  void update(const estimation::EstimatorInputs& inputs) override;

  geometry::Pose2D pose() const override;
  Eigen::Matrix3d covariance() const override;
  estimation::EstimatorCounters counters() const override { return counters_; }
  bool converged() const override { return true; }

 private:
  std::shared_ptr<SlamWorker> worker_;
  geometry::Pose2D odom_pose_;
  estimation::EstimatorCounters counters_;
};

}  // namespace mobot::server
