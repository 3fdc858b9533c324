#pragma once

#include <memory>

#include "drivers/backend.h"
#include "drivers/backend_factory.h"
#include "drivers/hardware/hardware_assembly.h"

namespace mobot::drivers::hardware {

// The real robot: the drivers of the config's hardware section, each on its own line and thread.
// Devices run in real time, so advance() has nothing to do; a device that is missing at start is
// not an error (the robot stays stopped and the device thread keeps looking for it).
class HardwareBackend final : public Backend {
 public:
  HardwareBackend(sim::RobotProfile profile, const BackendOptions& options);
  ~HardwareBackend() override;
  void stop_devices() override;

  std::string_view name() const override { return "hardware"; }
  const kinematics::RobotGeometry& geometry() const override { return geometry_; }
  DriverSet& drivers() override { return assembly_->drivers; }
  void advance(double) override {}
  std::vector<DeviceCounters> device_counters() const override;

 private:
  sim::RobotProfile profile_;
  BackendOptions options_;
  kinematics::RobotGeometry geometry_;
  std::unique_ptr<HardwareAssembly> assembly_;
};

// The drivers the hardware section may name, by role and driver: the one list a new driver
// joins.
std::span<const DeviceDriverEntry> device_drivers();

std::unique_ptr<Backend> make_hardware_backend(const BackendOptions& options);

}  // namespace mobot::drivers::hardware
