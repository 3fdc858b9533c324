#pragma once

namespace mobot::msgs {

// What a base's motor controllers are told: the wheels' angular speeds. A kinematic model makes
// it from a body velocity; a base driver turns it into the set-points of its controllers.
struct WheelCommand {
  double left_radps = 0.0;
  double right_radps = 0.0;
};

}  // namespace mobot::msgs
