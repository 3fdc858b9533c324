#pragma once

#include <cstdint>

namespace mobot::msgs {

// Cumulative encoder counts of a differential base, as read from the motor controllers.
struct WheelEncoders {
  double stamp_s = 0.0;
  std::int64_t left_ticks = 0;
  std::int64_t right_ticks = 0;
};

}  // namespace mobot::msgs
