#pragma once

#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::msgs {

// One ultrasonic (or IR) range sensor's latest reading: the nearest echo inside its cone.
struct RangeReading {
  geometry::Pose2D sensor_in_base;
  double cone_rad = 0.0;  // full opening angle
  double range_min_m = 0.0;
  double range_max_m = 0.0;
  double range_m = 0.0;  // range_max_m when nothing echoed
};

struct SonarRing {
  double stamp_s = 0.0;
  std::vector<RangeReading> readings;
};

}  // namespace mobot::msgs
