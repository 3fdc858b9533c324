#pragma once

#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "api/ports/control_port.h"
#include "core/control/path_tracker.h"
#include "core/navigation/goal_navigator.h"
#include "server/map_listener.h"
#include "server/planning_worker.h"
#include "server/plugins/registry.h"
#include "server/stage.h"

namespace mobot::server {

// Goal navigation: the goal navigator (lifecycle, tracking, sonar avoidance) on the control loop,
// the planning worker for plans and replans. Each tick it asks for a replan when the scan saw
// something on the path, commands the "navigation" mux source while a goal is active and
// publishes every goal change. Commands run on the control loop between ticks.
class NavigateStage final : public Stage, public MapListener {
 public:
  NavigateStage(PlanningWorker& worker, const PluginSet<control::PathTracker>& trackers,
                navigation::GoalNavigatorOptions options);

  std::string_view name() const override { return "navigate"; }
  void step(TickContext& context) override;

  // Plans from the current estimate with what the sensors see that the map does not have; `done`
  // runs on the worker thread.
  void plan(const api::GoalRequest& request, const TickContext& context, PlanningWorker::Done done);
  // Starts a planned goal, preempting the active one. Nothing when the controller is unknown:
  // then nothing changed.
  std::optional<navigation::Goal> start(const api::GoalRequest& request, const planning::Path& path,
                                        TickContext& context);
  // false when no goal has that id.
  bool cancel(std::int64_t id, TickContext& context);
  void end_active(navigation::GoalStatus status, const std::string& reason, TickContext& context);
  std::optional<navigation::Goal> find(std::int64_t id) const { return navigator_.find(id); }

  void prepare_map(const ActiveMap& map) override;
  void apply_map(const ActiveMap& map, TickContext& context) override;

 private:
  void request_replan(const TickContext& context);
  void collect_replan(TickContext& context);
  // Publishes the goal changes and refreshes the goal list the snapshot shows.
  void publish_changes(TickContext& context);

  PlanningWorker& worker_;
  const PluginSet<control::PathTracker>& trackers_;
  navigation::GoalNavigator navigator_;
  std::int64_t next_goal_id_ = 1;
  bool was_active_ = false;
  struct PendingReplan {
    std::int64_t goal_id;
    std::future<PlanningWorker::Outcome> outcome;
  };
  std::optional<PendingReplan> replan_;
  double last_replan_s_ = -1e9;
};

}  // namespace mobot::server
