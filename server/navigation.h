#pragma once

#include <cstdint>
#include <future>
#include <optional>
#include <string>
#include <vector>

#include "api/robot_port.h"
#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "core/msgs/laser_scan.h"
#include "core/msgs/sonar_ring.h"
#include "core/msgs/twist.h"
#include "core/navigation/goal.h"
#include "core/navigation/goal_navigator.h"
#include "server/config.h"
#include "server/planning_worker.h"

namespace mobot::server {

using api::GoalRequest;

// Goal navigation in the runtime: the goal navigator (lifecycle, tracking, sonar avoidance), the
// planning worker, and what the sensors tell planning about obstacles the map does not have. Not
// thread-safe: the Robot calls it under its mutex; only the planning itself runs elsewhere.
class Navigation {
 public:
  explicit Navigation(const Config& config);

  // Inflates the new active map for planning and returns its generation. Thread-safe; the caller
  // then ends the active goal.
  std::uint64_t set_map(const mapping::OccupancyGrid& map) { return worker_.set_map(map); }
  // Plans with the 3D-obstacle layer from now on, unless the map changed since `map_generation`.
  // Thread-safe.
  bool set_obstacle_layer(std::shared_ptr<const mapping::OccupancyGrid> layer,
                          std::uint64_t map_generation) {
    return worker_.set_obstacle_layer(std::move(layer), map_generation);
  }

  // Plans from `start` to the request's target on the worker, with the obstacles the laser saw
  // last; wait on the future without holding the Robot's mutex.
  std::future<PlanningWorker::Outcome> plan(const geometry::Pose2D& start,
                                            const GoalRequest& request);
  const navigation::Goal& start(const GoalRequest& request, const planning::Path& path,
                                double now_s);
  void end_active(navigation::GoalStatus status, const std::string& reason, double now_s) {
    navigator_.end_active(status, reason, now_s);
  }
  bool cancel(std::int64_t id, double now_s) { return navigator_.cancel(id, now_s); }

  // Remembers the scan's returns that the map does not explain (dropped obstacles, people), and
  // replans at once when one of them lies on the path being followed.
  void observe_scan(const msgs::LaserScan& scan, const geometry::Pose2D& sensor_in_map,
                    const geometry::Pose2D& base_in_map, double now_s);
  // Keeps the echoes the potential field should react to: not a wall of the map, and on the path.
  void observe_sonar(const msgs::SonarRing& ring, const geometry::Pose2D& base_in_map);

  // One control tick: the command for the navigation mux source while a goal is active.
  std::optional<msgs::Twist> tick(double now_s, const geometry::Pose2D& pose,
                                  const msgs::Twist& velocity);

  bool active() const { return navigator_.active_id().has_value(); }
  std::optional<navigation::Goal> find(std::int64_t id) const { return navigator_.find(id); }
  std::vector<navigation::Goal> list() const { return navigator_.list(); }
  std::vector<navigation::Goal> take_changes() { return navigator_.take_changes(); }

 private:
  bool explained_by_map(const geometry::Point2D& point_in_map) const;
  bool near_active_path(const geometry::Point2D& point_in_map, double within_m) const;
  void request_replan(const geometry::Pose2D& pose, double now_s);
  void collect_replan(double now_s);

  // A return nearer the path than this blocks it (the planner keeps this much clearance).
  const double blocking_distance_m_;
  PlanningWorker worker_;
  navigation::GoalNavigator navigator_;
  std::int64_t next_goal_id_ = 1;
  std::vector<geometry::Point2D> unexpected_points_;  // last scan, map frame
  std::vector<msgs::RangeReading> unexpected_echoes_;  // last sonar ring, map echoes removed
  struct PendingReplan {
    std::int64_t goal_id;
    std::future<PlanningWorker::Outcome> outcome;
  };
  std::optional<PendingReplan> replan_;
  double last_replan_s_ = -1e9;
};

}  // namespace mobot::server
