#pragma once

namespace mobot::msgs {

// A body-frame velocity command or measurement of a planar base.
struct Twist {
  double linear_mps = 0.0;
  double angular_radps = 0.0;

  bool operator==(const Twist&) const = default;
};

}  // namespace mobot::msgs
