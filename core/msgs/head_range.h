#pragma once

#include <optional>

namespace mobot::msgs {

// The ranger on the camera head (R4): its reading: the distance to the nearest echo across its cone, none when nothing
// echoed within range_max_m.
struct HeadRange {
  double stamp_s = 0.0;
  std::optional<double> range_m;
  double range_max_m = 0.0;
};

}  // namespace mobot::msgs
