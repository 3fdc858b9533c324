#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "drivers/yaml_option_reader.h"
#include "server/config.h"

namespace mobot::server {

// A plugin's section, with ConfigError naming the bad key.
using OptionReader = drivers::YamlOptionReader<ConfigError>;

// The config's top-level section `name` (slam, costmaps, ir_safety, ...), or an empty node when
// the config has none: every key of such a section is optional.
inline YAML::Node config_section(const YAML::Node& root, const char* name) {
  return root && root[name] ? YAML::Node(root[name]) : YAML::Node();
}

}  // namespace mobot::server
