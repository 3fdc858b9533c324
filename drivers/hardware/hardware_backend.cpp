#include "drivers/hardware/hardware_backend.h"

#include <algorithm>
#include <array>
#include <set>

#include "drivers/hardware/camera_devices.h"
#include "drivers/hardware/dashgo_devices.h"
#include "drivers/hardware/maestro_devices.h"
#include "drivers/hardware/modbus_devices.h"
#include "drivers/hardware/motion_mind_devices.h"
#include "drivers/hardware/sick_lms2xx_devices.h"
#include "drivers/hardware/ydlidar_devices.h"

namespace mobot::drivers::hardware {
namespace {

constexpr std::array kDrivers{
    DeviceDriverEntry{"base", "dashgo_arduino", make_dashgo_arduino},
    DeviceDriverEntry{"base", "motion_mind", make_motion_mind_base},
    DeviceDriverEntry{"laser", "ydlidar_g4", make_ydlidar_g4},
    DeviceDriverEntry{"laser", "sick_lms2xx", make_sick_lms2xx},
    DeviceDriverEntry{"ir", "sharp_ir_arduino", make_sharp_ir_arduino},
    DeviceDriverEntry{"bus", "modbus_rtu", make_modbus_rtu},
    DeviceDriverEntry{"tilt", "motion_mind", make_motion_mind_tilt},
    DeviceDriverEntry{"camera", "opencv", make_opencv_camera},
    DeviceDriverEntry{"pan_tilt", "pololu_maestro", make_pololu_maestro},
};

const DeviceDriverEntry& find_driver(const std::string& role, const std::string& driver) {
  std::set<std::string> roles;
  std::string drivers;
  for (const DeviceDriverEntry& entry : kDrivers) {
    if (entry.role == role && entry.driver == driver) return entry;
    roles.insert(entry.role);
    if (entry.role == role) drivers += (drivers.empty() ? "" : ", ") + std::string(entry.driver);
  }
  if (!roles.contains(role)) {
    std::string known;
    for (const std::string& name : roles) known += (known.empty() ? "" : ", ") + name;
    throw BackendError("hardware." + role + ": unknown device role; the roles are " + known);
  }
  throw BackendError("hardware." + role + ".driver: '" + driver + "' is not one of " + drivers);
}

}  // namespace

std::span<const DeviceDriverEntry> device_drivers() { return kDrivers; }

HardwareBackend::HardwareBackend(sim::RobotProfile profile, const BackendOptions& options)
    : profile_(std::move(profile)), options_(options), geometry_(sim::geometry_of(profile_)) {
  assembly_ =
      std::make_unique<HardwareAssembly>(HardwareAssembly{profile_, options_, {}, {}, nullptr, {}});
  const YAML::Node& section = options_.hardware;
  if (!section || !section.IsMap() || section.size() == 0) {
    throw BackendError(
        "hardware: the config names no devices; --backend hardware needs a hardware section "
        "with at least the base ({driver, device, baud})");
  }
  std::vector<std::string> roles;
  for (const auto& item : section) roles.push_back(item.first.as<std::string>());
  // A driver may build on another role's device (the tilt on the laser's scans and the base's
  // line, the pan/tilt head on the camera it turns): the roles are made in this order, whatever
  // the file's.
  static const std::vector<std::string> kOrder{"base", "laser",  "ir",      "bus",
                                               "tilt", "camera", "pan_tilt"};
  std::stable_sort(roles.begin(), roles.end(), [](const std::string& a, const std::string& b) {
    const auto rank = [](const std::string& role) {
      return std::find(kOrder.begin(), kOrder.end(), role) - kOrder.begin();
    };
    return rank(a) < rank(b);
  });
  for (const std::string& role : roles) {
    DeviceReader entry(section[role], "hardware." + role);
    std::string driver;
    entry.text("driver", driver);
    if (driver.empty()) throw BackendError("hardware." + role + ".driver: required");
    find_driver(role, driver).make(entry, *assembly_);
  }
  if (!assembly_->drivers.base) {
    throw BackendError("hardware.base: required (the motor base's driver and device)");
  }
  for (const auto& device : assembly_->devices) device->start();
}

HardwareBackend::~HardwareBackend() {
  // The threads stop before the drivers that read them go.
  stop_devices();
}

void HardwareBackend::stop_devices() {
  for (const auto& device : assembly_->devices) device->stop();
}

std::vector<DeviceCounters> HardwareBackend::device_counters() const {
  std::vector<DeviceCounters> out;
  for (const auto& device : assembly_->devices) {
    for (DeviceCounters& counters : device->counters()) out.push_back(std::move(counters));
  }
  return out;
}

std::unique_ptr<Backend> make_hardware_backend(const BackendOptions& options) {
  std::optional<sim::RobotProfile> profile = sim::profile_named(options.profile);
  if (!profile) {
    throw BackendError("robot.profile: no robot named '" + options.profile + "'");
  }
  return std::make_unique<HardwareBackend>(std::move(*profile), options);
}

}  // namespace mobot::drivers::hardware
