#pragma once

#include <string_view>
#include <vector>

#include "core/kinematics/robot_geometry.h"
#include "drivers/device_status.h"
#include "drivers/driver_set.h"
#include "drivers/sim_control.h"

namespace mobot::drivers {

// Where the devices come from: the simulator, or the real drivers named in the config. The
// runtime cannot tell them apart, except that only the simulator offers sim_control().
class Backend {
 public:
  virtual ~Backend() = default;

  virtual std::string_view name() const = 0;  // "sim" | "hardware"
  virtual const kinematics::RobotGeometry& geometry() const = 0;
  virtual DriverSet& drivers() = 0;
  // Lets `dt_s` of robot time pass for the devices, at the start of each control tick: the
  // simulator steps its world; real devices live in real time and only collect what arrived.
  virtual void advance(double dt_s) = 0;
  virtual SimControl* sim_control() { return nullptr; }
  // The real devices' counters for /metrics; the simulator has none.
  virtual std::vector<DeviceCounters> device_counters() const { return {}; }
  // Stops the real devices' threads (their listeners, such as the scan forwarder, call into the
  // runtime, which goes before the backend does). Idempotent; the simulator has no threads.
  virtual void stop_devices() {}
};

}  // namespace mobot::drivers
