#include "core/control/velocity_smoother.h"

#include <algorithm>

#include "core/numeric/step_toward.h"

namespace mobot::control {
namespace {}  // namespace

const msgs::Twist& VelocitySmoother::step(const msgs::Twist& target, double dt_s) {
  const msgs::Twist limited = clamp_to_limits(target, limits_);
  current_.linear_mps =
      step_toward(current_.linear_mps, limited.linear_mps, limits_.max_linear_accel_mps2 * dt_s);
  current_.angular_radps = step_toward(current_.angular_radps, limited.angular_radps,
                                       limits_.max_angular_accel_radps2 * dt_s);
  return current_;
}

}  // namespace mobot::control
