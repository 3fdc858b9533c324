#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/estimation/kalman_update.h"
#include "core/estimation/line_matcher.h"
#include "core/estimation/odometry_covariance.h"
#include "core/estimation/update_report.h"
#include "core/geometry/pose2d.h"
#include "core/perception/line_segment.h"

namespace mobot::estimation {

struct EkfLocalizerOptions {
  // Process noise Q = diag(k_right |ds_R|, k_left |ds_L|) (E2: 0.0003 each).
  WheelNoise wheel_noise;
  // Calibrated compass variance (E2 set 1); the datasheet alone would claim 3.04e-6.
  double compass_var_rad2 = 2.79e-4;
  // Omni-camera landmark bearing variance (E2 set 3).
  double bearing_var_rad2 = 2.992e-4;
  // Optional chi-square (1 dof) innovation gates for the compass and bearing updates; 0 disables.
  // Off by default: both are absolute measurements, and a gate that rejects them while the
  // estimate is wrong would lock the filter out of its own recovery.
  double compass_gate_chi2 = 0.0;
  double bearing_gate_chi2 = 0.0;
  LineMatcherOptions line_matching;
};

// The outcome of a line update: the fused rows, and which observation went to which map line.
struct LineUpdateReport {
  UpdateReport update;
  std::vector<LineMatch> matches;
};

// EKF localisation of a differential base in a known map (docs/algorithms.md E2). State (x, y,
// theta) in the map frame and its 3x3 covariance. Odometry drives the prediction; compass headings,
// laser line features and landmark bearings are independent updates that may be used in any
// combination and order. Each call either applies completely or, with a status saying why,
// leaves the filter untouched. Pure and deterministic: time only enters through the wheel travel.
class EkfLocalizer {
 public:
  explicit EkfLocalizer(const EkfLocalizerOptions& options = {}, const geometry::Pose2D& pose = {},
                        const Eigen::Matrix3d& covariance = Eigen::Matrix3d::Zero());

  // Re-initialises the estimate (operator's initial pose, relocalisation). The covariance must be
  // finite with a non-negative diagonal; it is symmetrised.
  UpdateReport set_pose(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance);

  // One odometry step from the distances each wheel rolled since the last one (E1 mean, E2 A, W
  // and Q). track_m must be positive.
  UpdateReport predict(double ds_right_m, double ds_left_m, double track_m);

  // Compass heading of the base in the map frame: z = theta + e, H = [0 0 1].
  UpdateReport update_compass(double heading_rad);

  // Lines extracted from one scan, in the sensor frame mounted at sensor_in_base, against the
  // map's lines (map frame). Observations are moved to the base frame (covariance included),
  // matched (see match_lines), and all matches fused in one stacked update.
  LineUpdateReport update_lines(const std::vector<perception::LineSegment>& observed_in_sensor,
                                const geometry::Pose2D& sensor_in_base,
                                const std::vector<perception::LineSegment>& map_lines);

  // Bearing of a landmark at a known map position, measured from the base centre relative to its
  // heading (the omni camera sits at the centre).
  UpdateReport update_bearing(double bearing_rad, const geometry::Point2D& landmark_in_map);

  const geometry::Pose2D& pose() const { return pose_; }
  const Eigen::Matrix3d& covariance() const { return covariance_; }
  const EkfLocalizerOptions& options() const { return options_; }

 private:
  UpdateReport correct(const MeasurementJacobian& h, const Eigen::MatrixXd& noise,
                       const Eigen::VectorXd& innovation, double gate_chi2);

  EkfLocalizerOptions options_;
  geometry::Pose2D pose_;
  Eigen::Matrix3d covariance_;
};

}  // namespace mobot::estimation
