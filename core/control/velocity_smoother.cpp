#include "core/control/velocity_smoother.h"

#include <algorithm>

namespace mobot::control {
namespace {

double approach(double current, double target, double max_step) {
  return current + std::clamp(target - current, -max_step, max_step);
}

}  // namespace

const msgs::Twist& VelocitySmoother::step(const msgs::Twist& target, double dt_s) {
  const msgs::Twist limited = clamp_to_limits(target, limits_);
  current_.linear_mps =
      approach(current_.linear_mps, limited.linear_mps, limits_.max_linear_accel_mps2 * dt_s);
  current_.angular_radps = approach(current_.angular_radps, limited.angular_radps,
                                    limits_.max_angular_accel_radps2 * dt_s);
  return current_;
}

}  // namespace mobot::control
