#pragma once

#include <Eigen/Core>
#include <numbers>
#include <vector>

#include "core/estimation/tricycle_motion_model.h"
#include "core/estimation/update_report.h"
#include "core/geometry/pose2d.h"

namespace mobot::estimation {

// docs/algorithms.md E3 defaults ("chosen" in the source: keep them configurable). The wheelbase is
// R3's d = sqrt(3.4) m.
struct LandmarkEkfOptions {
  double wheelbase_m = 1.8439088914585775;
  double speed_sigma_mps = 0.1;
  double steer_sigma_rad = 2.0 * std::numbers::pi / 180.0;
  double range_sigma_m = 0.1;
  double bearing_sigma_rad = 2.0 * std::numbers::pi / 180.0;
  // E3's Euler step by default. Against a finely integrated true path at dt = 0.1 s and 1 m/s,
  // Euler's model error shows as a mean NEES of about 4.6 instead of 3; kMidpoint removes it.
  TricycleIntegration integration = TricycleIntegration::kEuler;
};

// Range and bearing (relative to the heading, from the rear-axle centre) to one known landmark.
struct RangeBearingObservation {
  geometry::Point2D landmark_in_map;
  double range_m = 0.0;
  double bearing_rad = 0.0;
};

// EKF of a type 2 tricycle with range-bearing observations of known landmarks (docs/algorithms.md
// E3), generalised from two landmarks to any number: z = [r_1, b_1, ..., r_N, b_N] in one stacked
// update with R = diag(s_r^2, s_b^2, ...), bearings by atan2 with wrapped innovations.
// Each call either applies completely or reports why it left the filter untouched.
class LandmarkEkf {
 public:
  explicit LandmarkEkf(const LandmarkEkfOptions& options = {}, const geometry::Pose2D& pose = {},
                       const Eigen::Matrix3d& covariance = Eigen::Matrix3d::Zero());

  UpdateReport set_pose(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance);

  // One step of dt_s with drive speed v and steering angle alpha (|alpha| < pi/2), with
  // Q = diag(s_v^2, s_alpha^2) mapped through E3's W.
  UpdateReport predict(double speed_mps, double steer_rad, double dt_s);

  UpdateReport update(const std::vector<RangeBearingObservation>& observations);

  const geometry::Pose2D& pose() const { return pose_; }
  const Eigen::Matrix3d& covariance() const { return covariance_; }
  const LandmarkEkfOptions& options() const { return options_; }

 private:
  LandmarkEkfOptions options_;
  geometry::Pose2D pose_;
  Eigen::Matrix3d covariance_;
};

}  // namespace mobot::estimation
