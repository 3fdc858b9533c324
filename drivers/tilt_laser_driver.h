#pragma once

#include <optional>

#include "core/msgs/tilt_scan.h"
#include "core/perception/tilt_sweep.h"
#include "drivers/device_status.h"

namespace mobot::drivers {

// The nodding laser of 3D sweeps: the tilt axis and the laser that rides on it. A sweep starts
// at the lower limit switch; the driver yields each scan of the mode with the pitch its count
// implies (the hardware does not measure the pitch), at the mode's scan times.
class TiltLaserDriver {
 public:
  virtual ~TiltLaserDriver() = default;

  virtual perception::TiltRange range() const = 0;
  // Starts a sweep in `mode` at robot time `now_s`; a running sweep is abandoned.
  virtual void start(const perception::SweepMode& mode, double now_s) = 0;
  // The next scan that is due by `now_s`, or nothing (call again until nothing comes).
  virtual std::optional<msgs::TiltScan> poll(double now_s) = 0;
  // Parks the laser level and ends the sweep.
  virtual void stop() = 0;
  virtual DeviceStatus status() const = 0;
};

}  // namespace mobot::drivers
