#include "core/control/stop_and_rotate.h"

#include <algorithm>
#include <cmath>

namespace mobot::control {

StopAndRotate stop_and_rotate(const DynamicLimits& limits, const msgs::Twist& measured,
                              double heading_error_rad, double tolerance_rad) {
  const DynamicWindow window = reachable_window(limits, measured);
  const msgs::Twist stop = window.clamp({});
  StopAndRotate out;
  // Still rolling: brake both before turning (the turn is on the spot).
  if (stop.linear_mps > 0.0) {
    out.command = stop;
    return out;
  }
  if (std::abs(heading_error_rad) <= tolerance_rad) {
    out.command = stop;
    out.arrived = stop == msgs::Twist{};
    return out;
  }
  const double speed =
      std::clamp(std::sqrt(2.0 * limits.angular_accel_radps2 * std::abs(heading_error_rad)),
                 limits.min_in_place_angular_radps, limits.max_angular_radps);
  out.command = window.clamp({0.0, heading_error_rad > 0.0 ? -speed : speed});
  return out;
}

}  // namespace mobot::control
