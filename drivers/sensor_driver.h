#pragma once

#include <functional>
#include <optional>
#include <string_view>

#include "drivers/device_status.h"

namespace mobot::drivers {

// One sensor yielding stamped core messages (msgs::LaserScan, msgs::SonarRing, msgs::IrRing,
// msgs::CompassReading, msgs::LandmarkBearings, msgs::Image). The control loop polls it once per
// tick; it never blocks: a real device's reader thread leaves the newest reading for poll().
template <class Msg>
class SensorDriver {
 public:
  virtual ~SensorDriver() = default;

  // The sensor's name in /robot's sensors and the watchdog: "laser", "sonar", "ir", ...
  virtual std::string_view name() const = 0;
  // The rate the device delivers at, for the watchdog's time-out and the stream's advertisement.
  virtual double nominal_rate_hz() const = 0;
  // The reading that arrived since the last poll, stamped with the robot clock `now_s`, or
  // nothing when none is due.
  virtual std::optional<Msg> poll(double now_s) = 0;
  virtual DeviceStatus status() const = 0;
  // A real device's thread may also hand each reading to `listener` the moment it is complete
  // (stamp_s unset: the listener stamps it), so the stream can forward it at once instead of at
  // the next tick. Returns false for a driver whose readings exist only when polled (the
  // simulator's). Called before the devices start.
  virtual bool set_arrival_listener(std::function<void(const Msg&)> listener) {
    (void)listener;
    return false;
  }
};

}  // namespace mobot::drivers
