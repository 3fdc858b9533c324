#pragma once

#include <string>

#include "core/geometry/pose2d.h"

namespace mobot::msgs {

// The base touched something (a bumper, a motor controller's stall, the simulator's body check).
// The base has stopped; it stays stopped until somebody commands it again.
struct Contact {
  double stamp_s = 0.0;
  std::string with;       // what was hit, as far as the base knows ("wall", a box, "bumper")
  geometry::Pose2D pose;  // where the base stopped, in the frame the base knows (the sim's truth)
};

}  // namespace mobot::msgs
