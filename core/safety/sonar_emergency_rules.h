#pragma once

#include <cstddef>
#include <optional>
#include <string_view>

#include "core/msgs/sonar_ring.h"
#include "core/msgs/twist.h"
#include "core/safety/base_motion.h"

namespace mobot::safety {

// docs/algorithms.md R2: the Dashgo base driver's last-resort rules on its four sonars, s0 front
// left (+30 deg), s1 front, s2 front right (-30 deg), s3 rear. Distances are the sonar's own
// readings (from the sensor, not the body's edge).
struct SonarEmergencyOptions {
  // Which reading of the ring is which sonar.
  std::size_t front_left_index = 0;
  std::size_t front_index = 1;
  std::size_t front_right_index = 2;
  std::size_t rear_index = 3;
  // s0 or s2 this close while going forward: turn away on the spot.
  double side_turn_distance_m = 0.10;
  double turn_rate_radps = 0.2;
  // s1 this close while going forward, or s3 while reversing: stop.
  double front_stop_distance_m = 0.07;
  double rear_stop_distance_m = 0.07;
  // Slower than this (commanded and measured) is not going anywhere. Small: a creeping robot
  // still closes on the obstacle.
  double moving_speed_mps = 0.005;
};

enum class SonarRule {
  kFrontStop,  // s1 within front_stop_distance_m, going forward
  kRearStop,   // s3 within rear_stop_distance_m, reversing
  kTurnRight,  // s0 (left) within side_turn_distance_m, going forward
  kTurnLeft,   // s2 (right) within side_turn_distance_m, going forward
};

std::string_view to_string(SonarRule rule);  // "front_stop", "rear_stop", "turn_right", ...
// What the base does: "stop", "turn_left" or "turn_right".
std::string_view reaction_of(SonarRule rule);

struct SonarEmergency {
  SonarRule rule = SonarRule::kFrontStop;
  std::size_t sensor = 0;  // index in the ring of the reading that fired
  double range_m = 0.0;
  msgs::Twist command;  // what the base must do instead of what it was told
};

// The rule that fires for this ring, if any. The stops win over the turns (a stop is always safe);
// when s0 and s2 both fire the robot turns away from the nearer echo (toward the left on a tie).
// The rules ignore a reading that is not finite or is negative (a broken sonar is the watchdog's
// business) and a sonar the ring does not have. The base stationary (both speeds under
// moving_speed_mps) fires nothing: whatever is close, standing still hits nothing, and it leaves
// the operator free to drive away from it.
// Throws std::invalid_argument for negative or non-finite options.
std::optional<SonarEmergency> sonar_emergency(const msgs::SonarRing& ring, const BaseMotion& motion,
                                              const SonarEmergencyOptions& options = {});

}  // namespace mobot::safety
