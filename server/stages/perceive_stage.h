#pragma once

#include <functional>
#include <memory>

#include "core/perception/unmapped_obstacles.h"
#include "server/stage.h"

namespace mobot::server {

// What the laser and the sonars see that the planning map does not have: the points planning
// adds as obstacles, whether this tick's scan saw one on the active path (a replan), and the
// sonar echoes on the path that the potential field reacts to.
class PerceiveStage final : public Stage {
 public:
  using GridSource = std::function<std::shared_ptr<const planning::PlanningGrid>()>;

  // `planning_grid` gives the inflated active map with its 3D layer (thread-safe, cheap);
  // `blocking_distance_m`: a return nearer the path than this blocks it (the planner keeps this
  // much clearance).
  PerceiveStage(GridSource planning_grid, double blocking_distance_m);

  std::string_view name() const override { return "perceive"; }
  void step(TickContext& context) override;

 private:
  const GridSource planning_grid_;
  const double blocking_distance_m_;
  perception::UnmappedObstacles obstacles_;
};

}  // namespace mobot::server
