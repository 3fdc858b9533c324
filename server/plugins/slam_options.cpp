#include "server/plugins/slam_options.h"

#include "server/plugins/option_reader.h"

namespace mobot::server {

SlamWorkerOptions read_slam_options(const YAML::Node& root) {
  SlamWorkerOptions options;
  OptionReader reader(config_section(root, "slam"), "slam");
  slam::GraphSlamOptions& slam = options.slam;
  reader.number("max_range_m", slam.max_range_m, 1.0, 100.0);
  reader.number("min_travel_m", slam.min_travel_m, 0.0, 5.0);
  reader.number("min_rotation_rad", slam.min_rotation_rad, 0.0, 3.2);
  reader.number("resolution_m", slam.resolution_m, 0.01, 0.5);
  reader.number("loop_search_radius_m", slam.loop_search_radius_m, 0.5, 50.0);
  reader.number("loop_min_score", slam.loop_min_score, 0.0, 1.0);
  reader.number("match_covariance_scale", slam.match_covariance_scale, 0.001, 1000.0);
  reader.number("loop_covariance_scale", slam.loop_covariance_scale, 0.001, 1000.0);
  reader.number("odom_translation_sigma_per_m", slam.odom_translation_sigma_per_m, 0.0, 1.0);
  reader.number("odom_rotation_sigma_per_rad", slam.odom_rotation_sigma_per_rad, 0.0, 1.0);
  reader.number("odom_rotation_sigma_per_m", slam.odom_rotation_sigma_per_m, 0.0, 1.0);
  reader.number("match_field_sigma_m", slam.match_field_sigma_m, 0.01, 0.5);
  reader.number("local_map_spacing_m", slam.local_map_spacing_m, 0.0, 5.0);
  reader.number("map_period_s", options.map_period_s, 0.1, 60.0);
  // The rendered map may use a shorter range than matching: far returns still fix the pose
  // along a corridor, but drawn they smear its walls (0.5 % range noise).
  double map_max_range_m = slam.max_range_m;
  reader.number("map_max_range_m", map_max_range_m, 1.0, 100.0);
  reader.done();
  options.render.resolution_m = slam.resolution_m;
  options.render.max_range_m = map_max_range_m;
  // The tile lattice of the map topic: 64 cells per tile.
  options.render.align_m = 64 * slam.resolution_m;
  return options;
}

}  // namespace mobot::server
