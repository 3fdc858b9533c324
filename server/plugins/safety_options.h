#pragma once

#include <optional>

#include <yaml-cpp/yaml.h>

#include "core/safety/ir_safety.h"
#include "core/safety/sonar_emergency_rules.h"

namespace mobot::server {

// The reactive safety layers a robot has (docs/algorithms.md C6, R2), each a config section:
// `ir_safety` (the IR ring's urgent zone and bubble) and `sonar_emergency` (the Dashgo base's
// in-driver sonar rules, written for its four sonars). A layer runs when its section says
// `enabled: true`. Throws ConfigError naming a bad key.
std::optional<safety::IrSafetyOptions> read_ir_safety_options(const YAML::Node& root);
std::optional<safety::SonarEmergencyOptions> read_sonar_emergency_options(const YAML::Node& root);

}  // namespace mobot::server
