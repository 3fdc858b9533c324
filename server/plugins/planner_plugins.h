#pragma once

#include "core/planning/global_planner.h"
#include "server/plugins/registry.h"

namespace mobot::server {

// planners.astar: {cost_penalty_weight, max_escape_distance_m}
Registry<planning::GlobalPlanner>::Maker astar_plugin(const YAML::Node& section,
                                                      const PluginContext& context);
// planners.voronoi: {min_passage_width_m, off_roadmap_factor, max_escape_distance_m,
// waypoint_tolerance_m}
Registry<planning::GlobalPlanner>::Maker voronoi_plugin(const YAML::Node& section,
                                                        const PluginContext& context);

}  // namespace mobot::server
