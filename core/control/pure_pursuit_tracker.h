#pragma once

#include <optional>
#include <string_view>

#include "core/control/path_tracker.h"
#include "core/control/pure_pursuit.h"
#include "core/planning/path.h"

namespace mobot::control {

struct PurePursuitOptions {
  // Adaptive look-ahead (C3): L_d = lookahead_time_s * |v|, within [min, max]. A short look-ahead
  // hugs the path and oscillates at speed; a long one cuts corners.
  double lookahead_min_m = 1.0;
  double lookahead_max_m = 4.0;
  double lookahead_time_s = 1.5;
  double max_linear_mps = 1.0;
  double max_angular_radps = 1.0;
  // The base's tightest turn (a tricycle's d / tan(max_steer)); 0: it turns on the spot. A goal
  // inside the turning circle near the end of the path is reached by backing up straight first.
  double min_turning_radius_m = 0.0;
  // Slows down so it could stop at the goal with this deceleration.
  double approach_decel_mps2 = 0.25;
  // The speed it never drops below while driving (a steered base cannot steer standing still).
  double min_linear_mps = 0.1;
  double goal_tolerance_m = 0.1;
  double goal_tolerance_rad = 0.1;
  // Turns on the spot to the goal heading once there (a base that can); without it, and on a
  // car-like base, the goal heading is not pursued.
  bool align_heading = false;
  double align_gain = 1.5;
  double projection_window_m = 3.0;
};

// Pure pursuit (docs/algorithms.md C3) as a path tracker for any base: it asks for the curvature
// k = 2 sin(eta) / L_d towards the look-ahead point, as (v, w = v k); the kinematic model turns
// that into a steering angle atan(d k) on a tricycle or wheel speeds on a differential base.
class PurePursuitTracker final : public PathTracker {
 public:
  // Throws std::invalid_argument on out-of-range options.
  explicit PurePursuitTracker(const PurePursuitOptions& options = {});

  std::string_view name() const override { return "pure_pursuit"; }
  bool set_path(const planning::Path& path, std::optional<double> goal_heading_rad) override;
  void clear() override;
  msgs::Twist compute(const geometry::Pose2D& pose, const msgs::Twist& velocity,
                      double now_s) override;
  TrackerStatus status() const override { return status_; }

  // The look-ahead point of the last tick (for display and tests).
  const std::optional<LookaheadPoint>& lookahead() const { return lookahead_; }

 private:
  msgs::Twist pursue(const geometry::Pose2D& pose, const msgs::Twist& velocity);
  msgs::Twist align(const geometry::Pose2D& pose);
  // Whether the point lies inside one of the two circles the base turns on at its tightest.
  bool inside_turning_circle(const geometry::Pose2D& pose, geometry::Point2D point,
                             double margin_m) const;

  PurePursuitOptions options_;
  planning::Path path_;
  std::optional<double> goal_heading_rad_;
  TrackerStatus status_;
  std::optional<LookaheadPoint> lookahead_;
  bool reversing_ = false;
};

}  // namespace mobot::control
