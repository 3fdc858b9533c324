#include "server/plugins/costmap_options.h"

#include "server/plugins/option_reader.h"

namespace mobot::server {

CostmapOptions read_costmap_options(const YAML::Node& root, double inscribed_radius_m) {
  CostmapOptions options;
  OptionReader reader(config_section(root, "costmaps"), "costmaps");
  double inflation_m = options.global.inflation_margin_m;
  double scaling = options.global.cost_scaling_per_m;
  CostmapStageOptions& local = options.local;
  reader.number("inflation_radius_m", inflation_m, 0.0, 5.0);
  reader.number("cost_scaling_factor", scaling, 0.0, 100.0);
  reader.number("local_width_m", local.window.width_m, 0.5, 20.0);
  reader.number("local_height_m", local.window.height_m, 0.5, 20.0);
  reader.number("local_resolution_m", local.window.resolution_m, 0.01, 0.5);
  reader.number("obstacle_range_m", local.laser.obstacle_range_m, 0.1, 50.0);
  reader.number("raytrace_range_m", local.laser.raytrace_range_m, 0.1, 50.0);
  reader.done();
  options.global.inscribed_radius_m = inscribed_radius_m;
  options.global.inflation_margin_m = inflation_m;
  options.global.cost_scaling_per_m = scaling;
  local.inscribed_radius_m = inscribed_radius_m;
  local.inflation_radius_m = inflation_m;
  local.cost_scaling_per_m = scaling;
  return options;
}

}  // namespace mobot::server
