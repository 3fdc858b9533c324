#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/control/navigation_supervisor.h"
#include "core/control/path_tracker.h"
#include "core/control/potential_field_avoider.h"
#include "core/msgs/sonar_ring.h"
#include "core/msgs/twist.h"
#include "core/navigation/goal.h"
#include "core/planning/path.h"

namespace mobot::navigation {

struct GoalNavigatorOptions {
  control::NavigationSupervisorOptions supervisor;
  control::PotentialFieldOptions avoidance;
  // Finished goals kept for GET /goals.
  std::size_t history = 100;
  // A path that stays blocked is replanned (with the obstacles seen since) this many times, then
  // the goal fails with "blocked".
  int max_replans = 5;
  // A goal whose robot has not moved (this far, or turned this much) for this long while the
  // navigator commanded it fails with "stuck": wedged against something nothing else reports.
  double stuck_timeout_s = 15.0;
  double stuck_distance_m = 0.05;
  double stuck_angle_rad = 0.1;
};

// The navigation loop of docs/algorithms.md (Fig. 2.20) for one goal at a time: track the planned
// path with the goal's controller, hand over to sonar potential-field avoidance when something is
// within d0 ahead and back once clear, ask for a replan when the path stays blocked, and keep the
// goal lifecycle. Pure: the planner runs elsewhere and time is an argument.
class GoalNavigator {
 public:
  struct TickResult {
    std::optional<msgs::Twist> command;  // nothing when no goal is active
    bool replan_needed = false;          // the caller plans again and calls replan()
    control::NavigationMode mode = control::NavigationMode::kIdle;
  };

  explicit GoalNavigator(GoalNavigatorOptions options);

  // Starts a goal whose path is planned, followed by `tracker` (the goal's controller); an active
  // goal is canceled ("preempted"). A null tracker throws std::invalid_argument and changes
  // nothing: the active goal runs on.
  const Goal& start(Goal goal, const planning::Path& path,
                    std::unique_ptr<control::PathTracker> tracker, double now_s);
  // Ends the active goal, if any, with a final status and reason.
  void end_active(GoalStatus status, const std::string& reason, double now_s);
  // Cancels goal `id`: false when it is unknown; a finished goal is left as it is.
  bool cancel(std::int64_t id, double now_s);
  // A new path for the active goal after replan_needed; ignored when `id` is no longer active.
  void replan(std::int64_t id, const planning::Path& path, double now_s);

  TickResult tick(double now_s, const geometry::Pose2D& pose, const msgs::Twist& velocity,
                  std::span<const msgs::RangeReading> sonar);
  // Hands the active goal's tracker this tick's local costmap (before tick()).
  void set_local_costmap(std::shared_ptr<const planning::PlanningGrid> costmap) {
    if (tracker_) tracker_->set_local_costmap(std::move(costmap));
  }

  std::optional<std::int64_t> active_id() const;
  std::optional<Goal> find(std::int64_t id) const;
  std::vector<Goal> list() const;
  // Goals whose status or path changed since the last call, oldest change first.
  std::vector<Goal> take_changes();

 private:
  Goal* active();
  void finish(Goal& goal, GoalStatus status, const std::string& reason, double now_s);
  void follow(Goal& goal, const planning::Path& path, double now_s);
  void note_change(const Goal& goal);
  bool stuck(double now_s, const geometry::Pose2D& pose);

  GoalNavigatorOptions options_;
  std::deque<Goal> goals_;  // oldest first; at most one is active (the last)
  std::unique_ptr<control::PathTracker> tracker_;
  control::NavigationSupervisor supervisor_;
  control::PotentialFieldAvoider avoider_;
  bool replan_requested_ = false;
  std::vector<Goal> changes_;
  geometry::Pose2D last_moved_pose_;
  double last_moved_s_ = 0.0;
};

}  // namespace mobot::navigation
