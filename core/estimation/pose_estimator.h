#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/estimation/weighted_pose.h"
#include "core/estimation/wheel_odometry.h"
#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "core/msgs/compass_reading.h"
#include "core/estimation/particle_filter/free_space_sampler.h"
#include "core/estimation/particle_filter/likelihood_field.h"
#include "core/msgs/landmark_bearing.h"
#include "core/msgs/laser_scan.h"
#include "core/perception/line_segment.h"

namespace mobot::estimation {

// What localization knows of the active map, prepared once per map (off the control loop).
struct MapModel {
  std::shared_ptr<const mapping::OccupancyGrid> grid;
  std::vector<perception::LineSegment> wall_lines;  // map frame, with their free side
  // The grid's distance field and free cells (docs/algorithms.md E4), built with the default
  // LikelihoodFieldOptions; null when not prepared. Building them takes 108 ms for a 2000 x 2000
  // map: on the control loop that is five late ticks at every activation or method switch.
  std::shared_ptr<const LikelihoodField> likelihood_field;
  std::shared_ptr<const FreeSpaceSampler> free_space;
};

// This tick's readings, for an estimator to take what it uses. A null pointer: no new reading.
struct EstimatorInputs {
  double stamp_s = 0.0;
  const WheelTravel* travel = nullptr;  // the wheels' motion since the last tick
  double track_m = 0.0;
  const msgs::LaserScan* scan = nullptr;
  const msgs::CompassReading* compass = nullptr;
  const msgs::LandmarkBearings* bearings = nullptr;
};

struct EstimatorCounters {
  std::uint64_t scan_updates = 0;      // scans fused
  std::uint64_t features_matched = 0;  // scan features paired with the map
  std::uint64_t rejected_updates = 0;  // updates refused (gate, NaN)
};

// The default convergence rule, for estimators whose covariance is their whole belief (EKF):
// position standard deviation (largest axis of the x-y block) below 0.15 m and heading standard
// deviation below 0.1 rad. A non-finite covariance has not converged.
bool covariance_converged(const Eigen::Matrix3d& covariance);

// The robot's pose in the map frame, from odometry and whatever else the implementation fuses
// (EKF, particle filter, SLAM), chosen by name through the estimator registry. Called on the
// control loop once per tick: it must be cheap and never block.
class PoseEstimator {
 public:
  virtual ~PoseEstimator() = default;
  virtual std::string_view name() const = 0;
  // As /robot reports it: the name and, in parentheses, what is fused.
  virtual std::string method() const = 0;

  virtual void reset(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance) = 0;
  virtual void set_map(std::shared_ptr<const MapModel> map) = 0;
  virtual void update(const EstimatorInputs& inputs) = 0;

  virtual geometry::Pose2D pose() const = 0;
  virtual Eigen::Matrix3d covariance() const = 0;
  virtual EstimatorCounters counters() const = 0;

  // Spreads the belief over the free space of the map (global localization). False: this
  // estimator cannot (the caller answers 409), or it has no map with free space.
  virtual bool start_global_localization() { return false; }
  // Whether the estimate has settled (particle cloud tight; EKF: covariance small).
  virtual bool converged() const { return covariance_converged(covariance()); }
  // A sample of the belief for display (at most max_count), empty for single-hypothesis filters.
  virtual std::vector<WeightedPose> particles(std::size_t /*max_count*/) const { return {}; }
  // How many particles the belief holds (particles() may show fewer); 0 for the others.
  virtual std::size_t particle_count() const { return 0; }
};

}  // namespace mobot::estimation
