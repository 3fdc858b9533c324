#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "drivers/backend_factory.h"
#include "drivers/driver_set.h"
#include "drivers/hardware/hardware_device.h"
#include "drivers/hardware/laser_scan_source.h"
#include "drivers/serial/serial_port.h"
#include "drivers/sim/robot_profile.h"
#include "drivers/yaml_option_reader.h"

namespace mobot::drivers::hardware {

// One entry of the config's hardware section, read with errors that name the key
// ("hardware.laser.baud: ...").
using DeviceReader = YamlOptionReader<BackendError>;

// What the drivers of the config's hardware section build together: the driver set the runtime
// reads, and the devices (lines and threads) behind it.
struct HardwareAssembly {
  const sim::RobotProfile& profile;  // the robot's geometry and sensor mounts
  const BackendOptions& options;
  DriverSet drivers;
  std::vector<std::unique_ptr<HardwareDevice>> devices;
  // Set by a laser driver whose scans another device (the tilt) consumes; the backend builds
  // the roles in a fixed order (base, laser, ir, bus, tilt, camera), so it is there for them.
  LaserScanSource* laser_source = nullptr;
  // Set by a base driver whose line other boards share (R1's Motion Mind boards: the tilt's
  // board sits on the wheels' line), keyed by the device path.
  std::map<std::string, std::shared_ptr<void>> shared_lines;
};

// Builds the drivers of one entry into the assembly; throws BackendError for a bad option.
using DeviceFactory = void (*)(DeviceReader& entry, HardwareAssembly& assembly);

struct DeviceDriverEntry {
  const char* role;    // the key in the hardware section: base, laser, ir, tilt, bus, camera
  const char* driver;  // the entry's `driver`
  DeviceFactory make;
};

// `device` (required) and `baud` (default_baud unless given) of an entry.
serial::SerialOptions read_serial_options(DeviceReader& entry, unsigned default_baud);

}  // namespace mobot::drivers::hardware
