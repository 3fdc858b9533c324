#pragma once

#include <chrono>
#include <functional>
#include <vector>

#include "core/msgs/laser_scan.h"
#include "drivers/device_status.h"

namespace mobot::drivers::hardware {

// A real laser's scans as they arrive, for a driver that needs each of them (the nodding laser's
// sweep pairs every scan with the tilt's count), besides the control loop's newest-scan poll.
class LaserScanSource {
 public:
  using Listener =
      std::function<void(const msgs::LaserScan& scan, std::chrono::steady_clock::time_point at)>;

  virtual ~LaserScanSource() = default;
  // Each listener is called on the laser's device thread for every complete scan (the tilt's
  // sweep, the stream's forwarding on arrival); add them before the devices start.
  virtual void add_listener(Listener listener) = 0;
  virtual DeviceStatus status() const = 0;
};

}  // namespace mobot::drivers::hardware
