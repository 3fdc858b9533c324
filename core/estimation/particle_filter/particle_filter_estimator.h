#pragma once

#include <memory>
#include <string>

#include "core/estimation/particle_filter/particle_filter.h"
#include "core/estimation/pose_estimator.h"

namespace mobot::estimation {

struct ParticleFilterEstimatorOptions {
  ParticleFilterOptions filter;
};

// The particle filter of docs/algorithms.md E4 as a PoseEstimator. It integrates the wheels'
// travel itself (docs/algorithms.md E1) into its own odom frame, hands the filter that odometry
// and the scans, and reports the last filter estimate moved by the odometry since, so the pose
// moves smoothly every tick while the filter updates every 0.25 m / 0.2 rad. Without a map it
// dead-reckons (the cloud, and so the covariance, spreads) and never reports convergence.
class ParticleFilterEstimator final : public PoseEstimator {
 public:
  explicit ParticleFilterEstimator(const ParticleFilterEstimatorOptions& options = {});

  std::string_view name() const override { return "particle_filter"; }
  std::string method() const override { return "particle_filter(laser)"; }
  // A covariance that is not symmetric positive semi-definite, or a non-finite pose, is refused
  // (counted as a rejected update) and changes nothing.
  void reset(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance) override;
  // The likelihood field is the model's when it was prepared with this filter's
  // likelihood_max_distance_m, else built here; once per grid (a map set again is not rebuilt).
  void set_map(std::shared_ptr<const MapModel> map) override;
  void update(const EstimatorInputs& inputs) override;
  geometry::Pose2D pose() const override { return filter_.pose_at(odom_); }
  Eigen::Matrix3d covariance() const override { return filter_.covariance(); }
  EstimatorCounters counters() const override { return counters_; }

  bool start_global_localization() override;
  bool converged() const override { return filter_.converged(); }
  // Every k-th particle so that at most max_count come back, weights renormalised.
  std::vector<WeightedPose> particles(std::size_t max_count) const override;
  std::size_t particle_count() const override { return filter_.particles().size(); }

  const ParticleFilter& filter() const { return filter_; }
  // The odometry the estimator integrated (its own odom frame, from where it was constructed).
  const geometry::Pose2D& odometry() const { return odom_; }

 private:
  ParticleFilterEstimatorOptions options_;
  ParticleFilter filter_;
  geometry::Pose2D odom_;
  std::shared_ptr<const mapping::OccupancyGrid> grid_;
  EstimatorCounters counters_;
};

}  // namespace mobot::estimation
