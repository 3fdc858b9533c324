#include "server/plugins/planner_plugins.h"

#include <algorithm>
#include <numbers>
#include <stdexcept>

#include "core/planning/astar_planner.h"
#include "core/planning/hybrid_astar_planner.h"
#include "core/planning/voronoi_planner.h"
#include "server/plugins/option_reader.h"

namespace mobot::server {

Registry<planning::GlobalPlanner>::Maker astar_plugin(const YAML::Node& section,
                                                      const PluginContext&) {
  planning::AStarOptions options;
  OptionReader reader(section, "planners.astar");
  reader.number("cost_penalty_weight", options.cost_penalty_weight, 0.0, 100.0);
  reader.number("max_escape_distance_m", options.max_escape_distance_m, 0.0, 5.0);
  reader.done();
  return [options] { return std::make_unique<planning::AStarPlanner>(options); };
}

Registry<planning::GlobalPlanner>::Maker voronoi_plugin(const YAML::Node& section,
                                                        const PluginContext& context) {
  planning::VoronoiPlannerOptions options;
  // The roadmap keeps the middles of passages the robot fits through: at least its turning
  // diameter wide.
  options.roadmap.min_passage_width_m = 2.0 * context.navigation.inscribed_radius_m;
  OptionReader reader(section, "planners.voronoi");
  reader.number("min_passage_width_m", options.roadmap.min_passage_width_m, 0.0, 10.0);
  reader.number("off_roadmap_factor", options.off_roadmap_factor, 1.0, 100.0);
  reader.number("max_escape_distance_m", options.max_escape_distance_m, 0.0, 5.0);
  reader.number("waypoint_tolerance_m", options.waypoint_tolerance_m, 0.0, 1.0);
  reader.done();
  return [options] { return std::make_unique<planning::VoronoiPlanner>(options); };
}

Registry<planning::GlobalPlanner>::Maker hybrid_astar_plugin(const YAML::Node& section,
                                                             const PluginContext& context) {
  planning::HybridAStarOptions options;
  // The base's tightest turn. A base that turns on the spot (0) has none, but the search needs
  // one: the larger of 0.5 m and the inscribed radius gives arcs such a base follows at cruise
  // speed without stopping to turn, and keeps its body's swing within the inflation.
  options.min_turning_radius_m = context.min_turning_radius_m > 0.0
                                     ? context.min_turning_radius_m
                                     : std::max(0.5, context.navigation.inscribed_radius_m);
  // 0.5 m steps (R3: three 5 degree bins a full-lock step), shorter for a tight radius so one
  // step turns no more than about 22 degrees.
  options.primitive_length_m = std::min(0.5, options.min_turning_radius_m * std::numbers::pi / 8.0);
  options.footprint_length_m = context.geometry.footprint_length_m;
  options.footprint_width_m = context.geometry.footprint_width_m;
  options.footprint_offset_m = context.geometry.footprint_offset_m;
  options.inscribed_radius_m = context.navigation.inscribed_radius_m;
  OptionReader reader(section, "planners.hybrid_astar");
  reader.number("min_turning_radius_m", options.min_turning_radius_m, 0.05, 50.0);
  reader.number("primitive_length_m", options.primitive_length_m, 0.02, 5.0);
  reader.integer("steering_samples_per_side", options.steering_samples_per_side, 1, 8);
  reader.integer("heading_bins", options.heading_bins, 8, 720);
  reader.number("state_cell_m", options.state_cell_m, 0.01, 2.0);
  reader.number("cost_penalty_weight", options.cost_penalty_weight, 0.0, 100.0);
  reader.number("steering_penalty", options.steering_penalty, 0.0, 10.0);
  reader.number("steering_change_penalty", options.steering_change_penalty, 0.0, 10.0);
  int max_expansions = static_cast<int>(options.max_expansions);
  reader.integer("max_expansions", max_expansions, 100, 10000000);
  options.max_expansions = static_cast<std::size_t>(max_expansions);
  reader.number("collision_step_m", options.collision_step_m, 0.01, 1.0);
  reader.number("path_step_m", options.path_step_m, 0.01, 0.5);
  reader.integer("shot_interval", options.shot_interval, 1, 10000);
  reader.number("shot_always_within_m", options.shot_always_within_m, 0.0, 100.0);
  reader.number("max_shot_length_m", options.max_shot_length_m, 0.0, 1000.0);
  reader.number("goal_heading_tolerance_rad", options.goal_heading_tolerance_rad, 0.0,
                std::numbers::pi);
  reader.number("max_escape_distance_m", options.max_escape_distance_m, 0.0, 10.0);
  reader.flag("keep_way_out", options.keep_way_out);
  reader.done();
  // Built once now, so a combination the ranges cannot catch (a state cell not below the
  // primitive length) is a config error naming the section, not a failure at the first goal.
  try {
    planning::HybridAStarPlanner probe(options);
  } catch (const std::invalid_argument& error) {
    throw ConfigError(reader.path() + ": " + error.what());
  }
  return [options] { return std::make_unique<planning::HybridAStarPlanner>(options); };
}

}  // namespace mobot::server
