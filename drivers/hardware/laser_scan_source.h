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

// What SensorDriver::set_arrival_listener needs from a laser (PolledSensor's `subscribe`): each
// scan of `source` handed on as it arrives.
inline std::function<void(std::function<void(const msgs::LaserScan&)>)> arrivals_of(
    LaserScanSource& source) {
  return [&source](std::function<void(const msgs::LaserScan&)> listener) {
    source.add_listener([listener = std::move(listener)](const msgs::LaserScan& scan,
                                                         std::chrono::steady_clock::time_point) {
      listener(scan);
    });
  };
}

}  // namespace mobot::drivers::hardware
