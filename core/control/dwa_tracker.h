#pragma once

#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "core/control/dynamic_window.h"
#include "core/control/path_progress.h"
#include "core/control/path_tracker.h"
#include "core/geometry/pose2d.h"
#include "core/msgs/twist.h"
#include "core/planning/path.h"
#include "core/planning/planning_grid.h"

namespace mobot::control {

struct DwaOptions {
  // Speeds, accelerations and the control period: the Dashgo thesis's dwa_local_planner
  // configuration (v <= 0.3 m/s, |w| <= 1.0 rad/s, 0.4 rad/s on the spot, 1.5 m/s^2, 2.0 rad/s^2).
  DynamicLimits limits;
  // Each sampled (v, w) is simulated at constant velocity for this long (sim_time).
  double sim_time_s = 1.7;
  // Trajectory Rollout instead of DWA proper (base_local_planner with use_dwa false): sample the
  // velocities reachable within sim_time_s rather than one control period, simulate each
  // trajectory accelerating to its sample at the limits, and command the chosen sample, which the
  // velocity smoother ramps to at the same limits. For a base that accelerates slowly next to the control rate (the
  // Dashgo's 0.3 m/s^2 and 0.3 rad/s^2 give a one-period window of 6 mm/s and 6 mrad/s) the
  // constant-velocity arcs of that window barely differ, and the one it picks overshoots because
  // none of them accounts for the time it takes to brake a turn.
  bool accelerate_in_rollout = false;
  // Simulation steps: at most this far or this much turn apart (sim_granularity,
  // angular_sim_granularity).
  double sim_granularity_m = 0.025;
  double angular_sim_granularity_rad = 0.1;
  // Samples across the dynamic window (vx_samples 6-10 in the thesis, vth_samples 20); zero is
  // added to each when the window holds it.
  int linear_samples = 8;
  int angular_samples = 20;
  // dwa_local_planner's critics, per metre of distance (ROS scales its cell distances by the
  // resolution the same way): the trajectory's end to the path, its end to the local goal, and the
  // highest cell cost along it (0..252).
  double path_distance_bias = 32.0;
  double goal_distance_bias = 24.0;
  double occdist_scale = 0.01;
  // The "nose" point this far ahead of the end pose is scored too (ROS's alignment and goal-front
  // critics), so a trajectory is also judged by where it points; off within this distance of the
  // goal, where it would destabilise the final turn.
  double forward_point_distance_m = 0.325;
  // The local goal is the path point where the path leaves the local costmap; without a costmap,
  // the point this far along the path from the robot's projection.
  double local_goal_distance_m = 1.5;
  // How far ahead along the path the robot's projection is searched each tick.
  double projection_window_m = 2.0;
  // A best trajectory that does not score this much better than standing still makes no
  // progress: the tracker stops and reports itself blocked (boxed in, or the path is walled off).
  double min_improvement = 1e-3;
  // Within this distance of the goal, when no trajectory beats standing still (the goal lies off
  // to the side of a robot that stopped just outside the tolerance: every arc the window allows
  // passes it by), the robot turns on the spot to face the goal and drives straight at it, if
  // the cells on the way are traversable. 0: never.
  double approach_radius_m = 0.4;
  // The final approach starts within goal_tolerance_m of the goal and is latched: stop, turn to the
  // goal heading, arrive within goal_tolerance_rad.
  double goal_tolerance_m = 0.05;
  double goal_tolerance_rad = 0.05;
};

// The Dynamic Window Approach as ROS's dwa_local_planner (Fox, Burgard, Thrun 1997;
// docs/algorithms.md C5): each tick it samples (v, w) in the window reachable within one control
// period from the measured velocity, forward-simulates each for sim_time, rejects trajectories
// that cross a lethal, inscribed or unknown cell of the local costmap, scores the rest
//   path_distance_bias * d(end, path) + goal_distance_bias * d(end, local goal)
//   + occdist_scale * max cost  (+ the same two distances of the nose point)
// and commands the cheapest, preferring the faster of equal scores. No admissible trajectory, or
// none better than standing still, is a clear stop: zero command and blocked() true, except
// within approach_radius_m of the goal, where it turns to the goal and drives straight at it.
// Within the goal tolerance it stops and turns on the spot to the goal heading (stop_and_rotate). Without a local costmap
// every cell counts as free.
class DwaTracker : public PathTracker {
 public:
  // Throws std::invalid_argument on out-of-range options.
  explicit DwaTracker(const DwaOptions& options = {});

  std::string_view name() const override { return "dwa"; }
  bool set_path(const planning::Path& path, std::optional<double> goal_heading_rad) override;
  void clear() override;
  void set_local_costmap(std::shared_ptr<const planning::PlanningGrid> costmap) override {
    costmap_ = std::move(costmap);
  }
  msgs::Twist compute(const geometry::Pose2D& pose, const msgs::Twist& velocity,
                      double now_s) override;
  TrackerStatus status() const override { return progress_.status(); }

  const DwaOptions& options() const { return options_; }
  // The last compute() found no trajectory worth taking and commanded a stop.
  bool blocked() const { return blocked_; }
  // The trajectory chosen on the last tick (map-frame poses), empty when none was.
  const std::vector<geometry::Pose2D>& chosen_trajectory() const { return chosen_; }
  // Trajectories scored on the last tick, and how many of them were admissible.
  int trajectories_scored() const { return scored_; }
  int trajectories_admissible() const { return admissible_; }

 private:
  struct Scoring;
  msgs::Twist track(const geometry::Pose2D& pose, const msgs::Twist& velocity);
  // The approach_radius_m manoeuvre; nullopt when the goal is farther or the way is not free.
  std::optional<msgs::Twist> approach_goal(const geometry::Pose2D& pose,
                                           const msgs::Twist& velocity) const;

  DwaOptions options_;
  std::shared_ptr<const planning::PlanningGrid> costmap_;
  PathProgress progress_;
  bool blocked_ = false;
  std::vector<geometry::Pose2D> chosen_;
  int scored_ = 0;
  int admissible_ = 0;
};

}  // namespace mobot::control
