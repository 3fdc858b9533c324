#include "core/safety/sonar_emergency_rules.h"

#include <cmath>
#include <stdexcept>

namespace mobot::safety {
namespace {

void check(const SonarEmergencyOptions& options) {
  for (const double value :
       {options.side_turn_distance_m, options.turn_rate_radps, options.front_stop_distance_m,
        options.rear_stop_distance_m, options.moving_speed_mps}) {
    if (!std::isfinite(value) || value < 0.0) {
      throw std::invalid_argument("sonar emergency rules: distances and speeds must be >= 0");
    }
  }
}

// The reading of sonar `index` when it is within `limit_m`.
std::optional<double> within(const msgs::SonarRing& ring, std::size_t index, double limit_m) {
  if (index >= ring.readings.size()) return std::nullopt;
  const double range_m = ring.readings[index].range_m;
  if (!std::isfinite(range_m) || range_m < 0.0 || range_m > limit_m) return std::nullopt;
  return range_m;
}

}  // namespace

std::string_view to_string(SonarRule rule) {
  switch (rule) {
    case SonarRule::kFrontStop:
      return "front_stop";
    case SonarRule::kRearStop:
      return "rear_stop";
    case SonarRule::kTurnRight:
      return "turn_right";
    case SonarRule::kTurnLeft:
      return "turn_left";
  }
  return "unknown";
}

std::string_view reaction_of(SonarRule rule) {
  switch (rule) {
    case SonarRule::kFrontStop:
    case SonarRule::kRearStop:
      return "stop";
    case SonarRule::kTurnRight:
      return "turn_right";
    case SonarRule::kTurnLeft:
      return "turn_left";
  }
  return "stop";
}

std::optional<SonarEmergency> sonar_emergency(const msgs::SonarRing& ring, const BaseMotion& motion,
                                              const SonarEmergencyOptions& options) {
  check(options);
  const bool forward = motion.forward_mps() > options.moving_speed_mps;
  const bool reversing = motion.reverse_mps() > options.moving_speed_mps;

  if (forward) {
    if (const auto range_m = within(ring, options.front_index, options.front_stop_distance_m)) {
      return SonarEmergency{SonarRule::kFrontStop, options.front_index, *range_m, {}};
    }
  }
  if (reversing) {
    if (const auto range_m = within(ring, options.rear_index, options.rear_stop_distance_m)) {
      return SonarEmergency{SonarRule::kRearStop, options.rear_index, *range_m, {}};
    }
  }
  if (!forward) return std::nullopt;
  const auto left_m = within(ring, options.front_left_index, options.side_turn_distance_m);
  const auto right_m = within(ring, options.front_right_index, options.side_turn_distance_m);
  if (!left_m && !right_m) return std::nullopt;
  // Away from the nearer echo: an obstacle on the left turns the robot right (negative rate).
  if (left_m && (!right_m || *left_m < *right_m)) {
    return SonarEmergency{
        SonarRule::kTurnRight, options.front_left_index, *left_m, {0.0, -options.turn_rate_radps}};
  }
  return SonarEmergency{
      SonarRule::kTurnLeft, options.front_right_index, *right_m, {0.0, options.turn_rate_radps}};
}

}  // namespace mobot::safety
