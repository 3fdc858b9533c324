#include "server/plugins/planner_plugins.h"

#include "core/planning/astar_planner.h"
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

}  // namespace mobot::server
