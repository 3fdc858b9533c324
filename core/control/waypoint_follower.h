#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "core/control/lyapunov_controller.h"
#include "core/control/path_tracker.h"
#include "core/geometry/pose2d.h"
#include "core/msgs/twist.h"
#include "core/planning/path.h"

namespace mobot::control {

struct WaypointFollowerOptions {
  LyapunovGains gains;
  double max_linear_mps = 1.3;
  double max_angular_radps = 2.0;
  // The intermediate target ("carrot") slides along the path this far ahead of the robot's
  // projection. With k_v = 1 the cruise speed is about k_v * lookahead_m.
  double lookahead_m = 0.8;
  // Within this path length (or straight-line distance) of the goal the follower switches to full
  // C2 point stabilisation on the goal pose, and stays there.
  double final_approach_m = 0.8;
  // Final approach: C2's local-law radius, and the lateral gate that keeps the local law from
  // freezing an offset larger than the tolerance (see LyapunovOptions).
  double eps_rho_m = 0.21;
  double local_entry_max_lateral_m = 0.02;
  bool allow_reverse_at_goal = true;
  // Arrival: position and heading within tolerance and the measured velocity about zero.
  double goal_tolerance_m = 0.05;
  double goal_tolerance_rad = 0.05;
  double arrived_linear_mps = 0.05;
  double arrived_angular_radps = 0.1;
  // How far ahead along the path the robot's projection is searched each tick.
  double projection_window_m = 2.0;
  // A vertex where the path turns by more than corner_angle_rad holds the carrot, with the incoming
  // direction as target heading, until the robot is within corner_switch_radius_m of it; then the
  // carrot jumps ahead again. A carrot sliding round a corner at speed makes the robot overshoot
  // the turn (0.14 m on a 90 degree corner at 0.8 m look-ahead, against 0.09 m when held), and the
  // smoothed path's clearance (PathSmoother::max_shortcut_cost) is only about 0.13 m more than the
  // inscribed radius. The robot slows into the corner but does not stop.
  double corner_angle_rad = 0.35;
  double corner_switch_radius_m = 0.3;
};

// Follows a polyline of waypoints with the C2 Lyapunov law without stopping at each waypoint:
// the target of the global law is a carrot at lookahead_m along the path, with the path's
// direction there as target heading (so the h * phi term pulls the robot onto the path's
// direction, not just toward a point), forward only. Near the end the follower hands over to
// C2 point stabilisation (global then local law, reversing allowed) on the goal pose with the
// requested heading, and reports kArrived once within tolerance and stopped.
class WaypointFollower : public PathTracker {
 public:
  // Throws std::invalid_argument on out-of-range options.
  explicit WaypointFollower(const WaypointFollowerOptions& options = {});

  std::string_view name() const override { return "lyapunov"; }
  bool set_path(const planning::Path& path, std::optional<double> goal_heading_rad) override;
  void clear() override;
  msgs::Twist compute(const geometry::Pose2D& pose, const msgs::Twist& velocity,
                      double now_s) override;
  TrackerStatus status() const override { return status_; }

  const planning::Path& path() const { return path_; }
  const geometry::Pose2D& goal() const { return goal_; }
  // The law the final approach used on the last tick.
  LyapunovLaw final_law() const { return final_law_; }

 private:
  msgs::Twist track(const geometry::Pose2D& pose);
  // The carrot: lookahead_m ahead along the path, or held at the next corner not yet passed.
  geometry::Pose2D carrot(const geometry::Pose2D& pose);
  msgs::Twist approach(const geometry::Pose2D& pose, const msgs::Twist& velocity);

  WaypointFollowerOptions options_;
  LyapunovController carrot_controller_;
  LyapunovController goal_controller_;
  planning::Path path_;
  std::vector<double> corner_s_m_;  // arc lengths of the sharp vertices, ascending
  std::size_t next_corner_ = 0;     // corners before this one are passed
  geometry::Pose2D goal_;
  TrackerStatus status_;
  LyapunovLaw final_law_ = LyapunovLaw::kGlobal;
};

}  // namespace mobot::control
