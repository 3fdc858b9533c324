#include "core/planning/global_planner_factory.h"

namespace mobot::planning {

std::unique_ptr<GlobalPlanner> make_global_planner(std::string_view name,
                                                   const GlobalPlannerOptions& options) {
  if (name == "astar") return std::make_unique<AStarPlanner>(options.astar);
  if (name == "voronoi") return std::make_unique<VoronoiPlanner>(options.voronoi);
  return nullptr;
}

std::vector<std::string_view> global_planner_names() { return {"astar", "voronoi"}; }

}  // namespace mobot::planning
