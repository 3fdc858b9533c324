#pragma once

#include <memory>
#include <string_view>
#include <vector>

#include "core/planning/astar_planner.h"
#include "core/planning/global_planner.h"
#include "core/planning/voronoi_planner.h"

namespace mobot::planning {

// Options of every planner the factory can make; each reads its own part.
struct GlobalPlannerOptions {
  AStarOptions astar;
  VoronoiPlannerOptions voronoi;
};

// The planner registered under `name` (CONTRACT.md's "planner" field), or nullptr when no planner
// has that name.
std::unique_ptr<GlobalPlanner> make_global_planner(std::string_view name,
                                                   const GlobalPlannerOptions& options = {});

// The names make_global_planner knows, for config validation messages.
std::vector<std::string_view> global_planner_names();

}  // namespace mobot::planning
