#pragma once

#include <yaml-cpp/yaml.h>

#include "core/planning/planning_grid_builder.h"
#include "server/stages/costmap_stage.h"

namespace mobot::server {

// The costmaps of the config's `costmaps` section (docs/algorithms.md P3): inflation shared by the
// global (planning) and the local costmap, the local window and its sources. Every key optional,
// range-checked; `inscribed_radius_m` is navigation's. Throws ConfigError naming the key.
struct CostmapOptions {
  planning::PlanningGridOptions global;
  CostmapStageOptions local;
};

CostmapOptions read_costmap_options(const YAML::Node& root, double inscribed_radius_m);

}  // namespace mobot::server
