#include "drivers/sim/sim_pan_tilt.h"

#include <cmath>

namespace mobot::sim {

void SimPanTilt::set_target(const vision::PanTilt& joints) {
  vision::PanTilt next = target_;
  if (std::isfinite(joints.pan_rad)) next.pan_rad = joints.pan_rad;
  if (std::isfinite(joints.tilt_rad)) next.tilt_rad = joints.tilt_rad;
  target_ = head_.clamp(next);
}

}  // namespace mobot::sim
