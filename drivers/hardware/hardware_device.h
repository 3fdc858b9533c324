#pragma once

#include <vector>

#include "drivers/device_status.h"

namespace mobot::drivers::hardware {

// A device the hardware backend owns: a line and its thread, shared by the drivers that read it
// (the Dashgo's Arduino is the base and the sonar ring). Started once every driver exists.
class HardwareDevice {
 public:
  virtual ~HardwareDevice() = default;

  virtual void start() = 0;
  virtual void stop() = 0;
  // The counters of the device (or of each node on a bus), for /metrics.
  virtual std::vector<DeviceCounters> counters() const = 0;
};

}  // namespace mobot::drivers::hardware
