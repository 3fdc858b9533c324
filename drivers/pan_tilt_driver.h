#pragma once

#include "core/vision/pan_tilt_head.h"
#include "drivers/device_status.h"

namespace mobot::drivers {

// A camera's pan/tilt head (docs/algorithms.md R4): joint set-points in, the joints' positions
// out. The head slews at its own rates; set_target never blocks.
class PanTiltDriver {
 public:
  virtual ~PanTiltDriver() = default;

  virtual const vision::PanTiltHeadOptions& head() const = 0;
  // Clamped to the head's limits; NaN holds the axis where it is.
  virtual void set_target(const vision::PanTilt& joints) = 0;
  virtual vision::PanTilt target() const = 0;
  virtual vision::PanTilt current() const = 0;
  virtual DeviceStatus status() const = 0;
};

}  // namespace mobot::drivers
