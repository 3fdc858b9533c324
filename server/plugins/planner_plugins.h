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

// planners.hybrid_astar: {min_turning_radius_m, primitive_length_m, steering_samples_per_side,
// heading_bins, state_cell_m, cost_penalty_weight, steering_penalty, steering_change_penalty,
// max_expansions, collision_step_m, path_step_m, shot_interval, shot_always_within_m,
// max_shot_length_m, goal_heading_tolerance_rad, max_escape_distance_m, keep_way_out}; the body
// from the robot's geometry and navigation.inscribed_radius_m.
Registry<planning::GlobalPlanner>::Maker hybrid_astar_plugin(const YAML::Node& section,
                                                             const PluginContext& context);

}  // namespace mobot::server
