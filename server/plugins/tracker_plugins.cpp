#include "server/plugins/tracker_plugins.h"

#include <algorithm>
#include <stdexcept>

#include "core/control/dwa_tracker.h"
#include "core/control/pure_pursuit_tracker.h"
#include "core/control/vfh_tracker.h"
#include "core/control/waypoint_follower.h"
#include "server/plugins/option_reader.h"

namespace mobot::server {
namespace {

// The Dashgo's speeds and accelerations (DynamicLimits' defaults) within what this robot may do;
// each is an option no higher than that cap.
void read_dynamic_limits(OptionReader& reader, const PluginContext& context,
                         control::DynamicLimits& limits) {
  const double max_linear =
      std::min(context.navigation.max_linear_mps, context.limits.max_linear_mps);
  const double max_angular = context.limits.max_angular_radps;
  const double max_linear_accel = context.limits.max_linear_accel_mps2;
  const double max_angular_accel = context.limits.max_angular_accel_radps2;
  limits.max_linear_mps = std::min(limits.max_linear_mps, max_linear);
  limits.max_angular_radps = std::min(limits.max_angular_radps, max_angular);
  limits.min_in_place_angular_radps =
      std::min(limits.min_in_place_angular_radps, limits.max_angular_radps);
  limits.linear_accel_mps2 = std::min(limits.linear_accel_mps2, max_linear_accel);
  limits.angular_accel_radps2 = std::min(limits.angular_accel_radps2, max_angular_accel);
  reader.number("max_linear_mps", limits.max_linear_mps, 0.01, max_linear);
  reader.number("max_angular_radps", limits.max_angular_radps, 0.01, max_angular);
  reader.number("min_in_place_angular_radps", limits.min_in_place_angular_radps, 0.0, max_angular);
  reader.number("linear_accel_mps2", limits.linear_accel_mps2, 0.01, max_linear_accel);
  reader.number("angular_accel_radps2", limits.angular_accel_radps2, 0.01, max_angular_accel);
  // One tick of the control loop: the loop's own period unless the section overrides it.
  limits.control_period_s = context.control_period_s;
  reader.number("control_period_s", limits.control_period_s, 0.005, 0.2);
}

// What DWA and VFH take alike: the navigation section's goal tolerances and the dynamic limits.
template <class Options>
void read_local_planner_common(OptionReader& reader, const PluginContext& context,
                               Options& options) {
  options.goal_tolerance_m = context.navigation.goal_tolerance_m;
  options.goal_tolerance_rad = context.navigation.goal_tolerance_rad;
  read_dynamic_limits(reader, context, options.limits);
}

// Builds one instance now, so a combination the ranges cannot catch (a minimum in-place rate
// above the maximum rate) is a config error naming the section, not a failure at the first goal.
template <class Tracker, class Options>
Registry<control::PathTracker>::Maker checked_maker(const Options& options,
                                                    const OptionReader& reader) {
  try {
    Tracker probe(options);
  } catch (const std::invalid_argument& error) {
    throw ConfigError(reader.path() + ": " + error.what());
  }
  return [options] { return std::make_unique<Tracker>(options); };
}

}  // namespace

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

Registry<control::PathTracker>::Maker dwa_plugin(const YAML::Node& section,
                                                 const PluginContext& context) {
  control::DwaOptions options;
  OptionReader reader(section, "controllers.dwa");
  read_local_planner_common(reader, context, options);
  reader.number("sim_time_s", options.sim_time_s, 0.1, 5.0);
  reader.number("sim_granularity_m", options.sim_granularity_m, 0.005, 0.5);
  reader.number("angular_sim_granularity_rad", options.angular_sim_granularity_rad, 0.01, 1.0);
  reader.integer("linear_samples", options.linear_samples, 1, 50);
  reader.integer("angular_samples", options.angular_samples, 1, 100);
  reader.number("path_distance_bias", options.path_distance_bias, 0.0, 1000.0);
  reader.number("goal_distance_bias", options.goal_distance_bias, 0.0, 1000.0);
  reader.number("occdist_scale", options.occdist_scale, 0.0, 10.0);
  reader.number("forward_point_distance_m", options.forward_point_distance_m, 0.0, 2.0);
  reader.number("local_goal_distance_m", options.local_goal_distance_m, 0.1, 10.0);
  reader.number("projection_window_m", options.projection_window_m, 0.1, 10.0);
  reader.number("min_improvement", options.min_improvement, 0.0, 10.0);
  reader.number("approach_radius_m", options.approach_radius_m, 0.0, 2.0);
  reader.flag("accelerate_in_rollout", options.accelerate_in_rollout);
  reader.done();
  return checked_maker<control::DwaTracker>(options, reader);
}

Registry<control::PathTracker>::Maker vfh_plugin(const YAML::Node& section,
                                                 const PluginContext& context) {
  control::VfhOptions options;
  OptionReader reader(section, "controllers.vfh");
  read_local_planner_common(reader, context, options);
  reader.integer("sector_count", options.sector_count, 8, 360);
  reader.number("window_radius_m", options.window_radius_m, 0.2, 10.0);
  reader.number("unknown_certainty", options.unknown_certainty, 0.0, 1.0);
  reader.integer("smoothing_half_width", options.smoothing_half_width, 0, 10);
  reader.number("high_threshold", options.high_threshold, 0.001, 1000.0);
  reader.number("low_threshold", options.low_threshold, 0.0, 1000.0);
  reader.integer("wide_valley_sectors", options.wide_valley_sectors, 1, 360);
  reader.integer("min_valley_sectors", options.min_valley_sectors, 1, 360);
  reader.number("target_weight", options.target_weight, 0.0, 100.0);
  reader.number("heading_weight", options.heading_weight, 0.0, 100.0);
  reader.number("previous_weight", options.previous_weight, 0.0, 100.0);
  reader.number("lookahead_m", options.lookahead_m, 0.05, 5.0);
  reader.number("heading_gain", options.heading_gain, 0.01, 20.0);
  reader.number("in_place_turn_rad", options.in_place_turn_rad, 0.05, 3.2);
  reader.number("slowdown_density", options.slowdown_density, 0.001, 1000.0);
  reader.number("approach_time_s", options.approach_time_s, 0.05, 10.0);
  reader.number("projection_window_m", options.projection_window_m, 0.1, 10.0);
  reader.done();
  return checked_maker<control::VfhTracker>(options, reader);
}

Registry<control::PathTracker>::Maker pure_pursuit_plugin(const YAML::Node& section,
                                                          const PluginContext& context) {
  control::PurePursuitOptions options;
  options.max_linear_mps = std::min(context.navigation.max_linear_mps, context.limits.max_linear_mps);
  options.max_angular_radps = context.limits.max_angular_radps;
  options.min_turning_radius_m = context.min_turning_radius_m;
  options.goal_tolerance_m = context.navigation.goal_tolerance_m;
  options.goal_tolerance_rad = context.navigation.goal_tolerance_rad;
  // A base that turns on the spot ends facing the goal heading, as the other trackers do.
  options.align_heading = context.min_turning_radius_m == 0.0;
  OptionReader reader(section, "controllers.pure_pursuit");
  reader.number("lookahead_min_m", options.lookahead_min_m, 0.1, 20.0);
  reader.number("lookahead_max_m", options.lookahead_max_m, 0.1, 20.0);
  reader.number("lookahead_time_s", options.lookahead_time_s, 0.0, 10.0);
  reader.number("max_linear_mps", options.max_linear_mps, 0.01, options.max_linear_mps);
  reader.number("approach_decel_mps2", options.approach_decel_mps2, 0.01, 10.0);
  reader.number("min_linear_mps", options.min_linear_mps, 0.0, options.max_linear_mps);
  reader.flag("align_heading", options.align_heading);
  reader.number("align_gain", options.align_gain, 0.01, 20.0);
  reader.number("projection_window_m", options.projection_window_m, 0.1, 20.0);
  reader.done();
  return checked_maker<control::PurePursuitTracker>(options, reader);
}

}  // namespace mobot::server
