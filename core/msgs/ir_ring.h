#pragma once

#include <vector>

#include "core/msgs/sonar_ring.h"

namespace mobot::msgs {

// The infrared range sensors of a base, read together: each a narrow cone with a short range.
struct IrRing {
  double stamp_s = 0.0;
  std::vector<RangeReading> readings;
};

}  // namespace mobot::msgs
