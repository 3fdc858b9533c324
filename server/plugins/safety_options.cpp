#include "server/plugins/safety_options.h"

#include "server/plugins/option_reader.h"

namespace mobot::server {
std::optional<safety::IrSafetyOptions> read_ir_safety_options(const YAML::Node& root) {
  OptionReader reader(config_section(root, "ir_safety"), "ir_safety");
  bool enabled = false;
  safety::IrSafetyOptions options;
  reader.flag("enabled", enabled);
  reader.number("urgent_radius_m", options.urgent_radius_m, 0.05, 1.0);
  reader.number("back_off_speed_mps", options.back_off_speed_mps, 0.01, 1.0);
  reader.number("back_off_distance_m", options.back_off_distance_m, 0.0, 1.0);
  reader.done();
  if (!enabled) return std::nullopt;
  return options;
}

std::optional<safety::SonarEmergencyOptions> read_sonar_emergency_options(const YAML::Node& root) {
  OptionReader reader(config_section(root, "sonar_emergency"), "sonar_emergency");
  bool enabled = false;
  safety::SonarEmergencyOptions options;
  reader.flag("enabled", enabled);
  reader.number("side_turn_distance_m", options.side_turn_distance_m, 0.0, 1.0);
  reader.number("front_stop_distance_m", options.front_stop_distance_m, 0.0, 1.0);
  reader.number("rear_stop_distance_m", options.rear_stop_distance_m, 0.0, 1.0);
  reader.number("turn_rate_radps", options.turn_rate_radps, 0.01, 2.0);
  reader.done();
  if (!enabled) return std::nullopt;
  return options;
}

}  // namespace mobot::server
