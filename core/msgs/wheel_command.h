#pragma once

namespace mobot::msgs {

// What a base's motor controllers are told. A differential base: each wheel's angular speed. A
// steered base (the tricycles): the driven wheel's ground speed and the steering angle, and its
// left/right fields stay zero. A kinematic model makes it from a body velocity; a base driver turns
// it into the set-points of its controllers.
struct WheelCommand {
  double left_radps = 0.0;
  double right_radps = 0.0;
  double drive_mps = 0.0;
  double steering_rad = 0.0;
};

}  // namespace mobot::msgs
