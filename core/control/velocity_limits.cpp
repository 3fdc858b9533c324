#include "core/control/velocity_limits.h"

#include <algorithm>

namespace mobot::control {

msgs::Twist clamp_to_limits(const msgs::Twist& command, const VelocityLimits& limits) {
  return {std::clamp(command.linear_mps, -limits.max_linear_mps, limits.max_linear_mps),
          std::clamp(command.angular_radps, -limits.max_angular_radps, limits.max_angular_radps)};
}

}  // namespace mobot::control
