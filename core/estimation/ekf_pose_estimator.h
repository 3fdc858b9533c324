#pragma once

#include <string>

#include "core/estimation/ekf_localizer.h"
#include "core/estimation/pose_estimator.h"
#include "core/perception/line_extractor.h"

namespace mobot::estimation {

struct EkfPoseEstimatorOptions {
  // The measurement sets of docs/algorithms.md E2; each can be switched off to see its effect.
  // With none, the filter only predicts: dead reckoning with an honest, growing covariance.
  bool fuse_compass = true;
  bool fuse_lines = true;
  bool fuse_bearing = true;
  // The name it is registered under: "ekf", or "odometry" for the predict-only filter.
  std::string name = "ekf";
  EkfLocalizerOptions filter;
  perception::LineExtractorOptions lines;
};

// The EKF of docs/algorithms.md E2 as a PoseEstimator: predicts from the wheels' travel and
// fuses the compass, the scan's lines matched to the map's walls and the landmark bearings.
class EkfPoseEstimator final : public PoseEstimator {
 public:
  explicit EkfPoseEstimator(EkfPoseEstimatorOptions options);

  std::string_view name() const override { return options_.name; }
  std::string method() const override;
  void reset(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance) override;
  void set_map(std::shared_ptr<const MapModel> map) override { map_ = std::move(map); }
  void update(const EstimatorInputs& inputs) override;
  geometry::Pose2D pose() const override { return ekf_.pose(); }
  Eigen::Matrix3d covariance() const override { return ekf_.covariance(); }
  EstimatorCounters counters() const override { return counters_; }

 private:
  void fuse_scan(const msgs::LaserScan& scan);

  EkfPoseEstimatorOptions options_;
  EkfLocalizer ekf_;
  perception::LineExtractor line_extractor_;
  std::shared_ptr<const MapModel> map_;
  EstimatorCounters counters_;
};

}  // namespace mobot::estimation
