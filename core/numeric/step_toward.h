#pragma once

#include <algorithm>

namespace mobot {

// The value moved toward the target by at most max_step (an acceleration limit over one tick).
inline double step_toward(double value, double target, double max_step) {
  return value + std::clamp(target - value, -max_step, max_step);
}

}  // namespace mobot
