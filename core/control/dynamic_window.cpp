#include "core/control/dynamic_window.h"

#include <algorithm>
#include <cmath>

#include "core/numeric/finite.h"

namespace mobot::control {
namespace {

// [value - step, value + step] within [lo, hi]; a value outside gives the nearest bound.
void window_around(double value, double step, double lo, double hi, double& out_lo,
                   double& out_hi) {
  out_lo = std::clamp(value - step, lo, hi);
  out_hi = std::clamp(value + step, lo, hi);
}

}  // namespace

bool valid(const DynamicLimits& limits) {
  return finite_positive(limits.max_linear_mps) && finite_positive(limits.max_angular_radps) &&
         finite_positive(limits.linear_accel_mps2) &&
         finite_positive(limits.angular_accel_radps2) && finite_positive(limits.control_period_s) &&
         std::isfinite(limits.min_in_place_angular_radps) &&
         limits.min_in_place_angular_radps >= 0.0 &&
         limits.min_in_place_angular_radps <= limits.max_angular_radps;
}

msgs::Twist DynamicWindow::clamp(const msgs::Twist& command) const {
  return {std::clamp(command.linear_mps, min_linear_mps, max_linear_mps),
          std::clamp(command.angular_radps, min_angular_radps, max_angular_radps)};
}

bool DynamicWindow::contains(const msgs::Twist& command, double slack) const {
  return command.linear_mps >= min_linear_mps - slack &&
         command.linear_mps <= max_linear_mps + slack &&
         command.angular_radps >= min_angular_radps - slack &&
         command.angular_radps <= max_angular_radps + slack;
}

DynamicWindow reachable_window(const DynamicLimits& limits, const msgs::Twist& measured) {
  DynamicWindow window;
  const double v = std::isfinite(measured.linear_mps) ? measured.linear_mps : 0.0;
  const double w = std::isfinite(measured.angular_radps) ? measured.angular_radps : 0.0;
  window_around(v, limits.linear_accel_mps2 * limits.control_period_s, 0.0, limits.max_linear_mps,
                window.min_linear_mps, window.max_linear_mps);
  window_around(w, limits.angular_accel_radps2 * limits.control_period_s, -limits.max_angular_radps,
                limits.max_angular_radps, window.min_angular_radps, window.max_angular_radps);
  return window;
}

}  // namespace mobot::control
