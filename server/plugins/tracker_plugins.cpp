#include "server/plugins/tracker_plugins.h"

#include "core/control/waypoint_follower.h"
#include "server/plugins/option_reader.h"

namespace mobot::server {

Registry<control::PathTracker>::Maker lyapunov_plugin(const YAML::Node& section,
                                                      const PluginContext& context) {
  control::WaypointFollowerOptions options;
  options.goal_tolerance_m = context.navigation.goal_tolerance_m;
  options.goal_tolerance_rad = context.navigation.goal_tolerance_rad;
  options.max_linear_mps = context.navigation.max_linear_mps;
  options.max_angular_radps = context.limits.max_angular_radps;
  // Point stabilisation swings the body on a curve; started late it happens where the path
  // ended (a goal just past a door must not be approached with the footprint in the doorway).
  options.final_approach_m = 0.4;
  OptionReader reader(section, "controllers.lyapunov");
  reader.number("lookahead_m", options.lookahead_m, 0.05, 5.0);
  reader.number("final_approach_m", options.final_approach_m, 0.05, 5.0);
  reader.number("eps_rho_m", options.eps_rho_m, 0.0, 2.0);
  reader.flag("allow_reverse_at_goal", options.allow_reverse_at_goal);
  reader.number("corner_angle_rad", options.corner_angle_rad, 0.0, 3.2);
  reader.number("corner_switch_radius_m", options.corner_switch_radius_m, 0.0, 2.0);
  reader.done();
  return [options] { return std::make_unique<control::WaypointFollower>(options); };
}

}  // namespace mobot::server
