#pragma once

#include <yaml-cpp/yaml.h>

#include "server/mapping/slam_worker.h"

namespace mobot::server {

// The mapping session's options from the config's `slam` section (docs/algorithms.md E5); every
// key optional, each range-checked. Throws ConfigError naming the key.
SlamWorkerOptions read_slam_options(const YAML::Node& root);

}  // namespace mobot::server
