#include "server/stages/navigate_stage.h"

#include <chrono>

namespace mobot::server {
namespace {

// Seen from afar by the laser, an obstacle on the path is planned around before the sonar has to
// swerve; at most once a second, so a person walking along does not thrash the planner.
constexpr double kReplanInterval_s = 1.0;

nlohmann::json goal_event(const navigation::Goal& goal) {
  nlohmann::json detail{{"id", goal.id},
                        {"status", navigation::to_string(goal.status)},
                        {"x", goal.target.x},
                        {"y", goal.target.y}};
  if (!goal.reason.empty()) detail["reason"] = goal.reason;
  if (goal.replans > 0) detail["replans"] = goal.replans;
  return detail;
}

}  // namespace

NavigateStage::NavigateStage(PlanningWorker& worker,
                             const PluginSet<control::PathTracker>& trackers,
                             navigation::GoalNavigatorOptions options)
    : worker_(worker), trackers_(trackers), navigator_(options) {}

void NavigateStage::plan(const api::GoalRequest& request, const TickContext& context,
                         PlanningWorker::Done done) {
  worker_.plan(context.pose, request.target, request.planner, context.unmapped_points,
               std::move(done));
}

std::optional<navigation::Goal> NavigateStage::start(const api::GoalRequest& request,
                                                     const planning::Path& path,
                                                     TickContext& context) {
  auto tracker = trackers_.make(request.controller);
  if (!tracker) return std::nullopt;
  navigation::Goal goal;
  goal.id = next_goal_id_++;
  goal.target = request.target;
  goal.has_heading = request.has_heading;
  goal.planner = request.planner;
  goal.controller = request.controller;
  replan_.reset();
  const navigation::Goal started =
      navigator_.start(std::move(goal), path, std::move(tracker), context.now_s);
  publish_changes(context);
  return started;
}

bool NavigateStage::cancel(std::int64_t id, TickContext& context) {
  if (!navigator_.cancel(id, context.now_s)) return false;
  publish_changes(context);
  return true;
}

void NavigateStage::end_active(navigation::GoalStatus status, const std::string& reason,
                               TickContext& context) {
  navigator_.end_active(status, reason, context.now_s);
  publish_changes(context);
}

void NavigateStage::request_replan(const TickContext& context) {
  const auto id = navigator_.active_id();
  if (!id || replan_) return;
  const auto goal = navigator_.find(*id);
  replan_ = PendingReplan{
      goal->id, worker_.plan(context.pose, goal->target, goal->planner, context.unmapped_points)};
  last_replan_s_ = context.now_s;
}

void NavigateStage::collect_replan(TickContext& context) {
  if (!replan_ || replan_->outcome.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    return;
  }
  PlanningWorker::Outcome outcome = replan_->outcome.get();
  const std::int64_t goal_id = replan_->goal_id;
  replan_.reset();
  if (navigator_.active_id() != goal_id) return;
  if (outcome.error) {
    navigator_.end_active(navigation::GoalStatus::kFailed,
                          std::string(planning::error_code(*outcome.error)), context.now_s);
  } else {
    navigator_.replan(goal_id, outcome.path, context.now_s);
  }
}

void NavigateStage::step(TickContext& context) {
  collect_replan(context);
  if (context.scan_blocks_path && context.now_s - last_replan_s_ >= kReplanInterval_s) {
    request_replan(context);
  }
  navigator_.set_local_costmap(context.local_costmap);
  const auto result = navigator_.tick(context.now_s, context.pose, context.odometry.twist,
                                      context.avoidance_echoes);
  if (result.replan_needed) request_replan(context);
  if (result.command) {
    context.mux_requests.push_back({"navigation", *result.command});
  } else if (was_active_) {
    // The goal ended: the last navigation command must not live on until its mux time-out.
    context.mux_requests.push_back({"navigation", std::nullopt});
  }
  was_active_ = result.command.has_value();
  publish_changes(context);
}

void NavigateStage::publish_changes(TickContext& context) {
  const std::vector<navigation::Goal> changes = navigator_.take_changes();
  // Every start, replan and end of a goal is a change: without one, what the context holds of
  // the goals is still true, and the tick copies nothing.
  if (changes.empty()) return;
  const auto active = navigator_.active_id();
  context.navigating = active.has_value();
  context.active_path = active ? navigator_.find(*active)->path : std::vector<geometry::Point2D>{};
  for (const auto& goal : changes) {
    context.bus->goals.publish(
        {context.now_s, goal, goal.status == navigation::GoalStatus::kActive});
    context.event("goal", goal_event(goal));
  }
  context.goals = std::make_shared<const std::vector<navigation::Goal>>(navigator_.list());
}

void NavigateStage::prepare_map(const ActiveMap& map) {
  std::vector<std::vector<geometry::Point2D>> zones;
  for (const auto& zone : *map.zones) zones.push_back(zone.polygon);
  worker_.set_map(*map.grid, std::move(zones), map.generation);
}

void NavigateStage::apply_map(const ActiveMap&, TickContext& context) {
  end_active(navigation::GoalStatus::kCanceled, "map_changed", context);
  if (auto costmap = worker_.static_grid()) {
    context.bus->costmap.publish({context.now_s, std::move(costmap), false});
  }
}

}  // namespace mobot::server
