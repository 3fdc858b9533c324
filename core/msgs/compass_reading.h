#pragma once

namespace mobot::msgs {

// Heading of the base in the map frame (the compass is calibrated to it), radians CCW.
struct CompassReading {
  double stamp_s = 0.0;
  double heading_rad = 0.0;
};

}  // namespace mobot::msgs
