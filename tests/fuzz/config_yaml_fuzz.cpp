// libFuzzer target: mobotd's config file (server/config_parser: parse_config, then
// check_config_rules) on arbitrary text. The plugins' own sections (server/plugins) are not
// covered: reading them builds the planners, trackers and estimators, which needs most of the
// core. Beyond not crashing: the text becomes a config whose values are within their documented
// ranges, or a ConfigError; no other exception (a YAML conversion error, say) escapes.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "server/config_parser.h"

namespace {

void check(bool condition) {
  if (!condition) __builtin_trap();
}

void check_ranges(const mobot::server::Config& config) {
  const auto& robot = config.robot;
  check(robot.control_rate_hz >= 5.0 && robot.control_rate_hz <= 200.0);
  check(robot.laser_rate_hz >= 1.0 && robot.laser_rate_hz <= robot.control_rate_hz);
  check(robot.teleop_ttl_ms >= 50 && robot.teleop_ttl_ms <= 1000);
  check(robot.realtime_priority >= 0 && robot.realtime_priority <= 99);
  check(!robot.mux_sources.empty());
  check(config.sim.time_scale >= 0.1 && config.sim.time_scale <= 100.0);
  check(config.navigation.max_linear_mps <= robot.limits.max_linear_mps);
  check(config.stream.max_frames_per_topic >= 1 && config.stream.max_frames_per_topic <= 64);
  check(config.backend == "sim" || config.backend == "hardware");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const mobot::server::Config config = mobot::server::parse_config(text, "fuzz.yaml");
    mobot::server::check_config_rules(config);
    check_ranges(config);
  } catch (const mobot::server::ConfigError&) {
  }
  return 0;
}
