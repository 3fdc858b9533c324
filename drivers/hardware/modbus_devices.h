#pragma once

#include <optional>
#include <vector>

#include "drivers/hardware/hardware_assembly.h"
#include "drivers/modbus/modbus_rtu_bus.h"

namespace mobot::drivers::hardware {

// R1's RS-485 sensor bus as one of the backend's devices: the bus master's thread, and the
// counters of the bus and of each of its nodes for /metrics.
class ModbusSensorBus final : public HardwareDevice {
 public:
  // Throws std::invalid_argument for options the bus refuses (see ModbusRtuBus).
  explicit ModbusSensorBus(const modbus::ModbusRtuBusOptions& options) : bus_(options) {}

  void start() override { bus_.start(); }
  void stop() override { bus_.stop(); }
  // "bus" (the whole line), then one entry per node: "compass", "sonar<id>" for each sonar in
  // ring order, "limit_switch".
  std::vector<DeviceCounters> counters() const override;

  // Whether the limit switch is pressed; nothing before its first reading and while the bus or
  // the switch's node is not ok, since a stale "released" must not be trusted.
  std::optional<bool> limit_switch_pressed() const;

  const modbus::ModbusRtuBus& bus() const { return bus_; }

 private:
  modbus::ModbusRtuBus bus_;
};

// bus: {driver: modbus_rtu, device, baud: 115200, compass_node: 1, sonar_nodes: [2..9] (one per
// sonar of the robot profile, in its order), limit_switch_node: 10, heading_offset_rad: 0,
// response_timeout_s: 0.02}: the compass and the sonar ring. The rates are the robot's
// compass_rate_hz and sonar_rate_hz.
void make_modbus_rtu(DeviceReader& entry, HardwareAssembly& assembly);

}  // namespace mobot::drivers::hardware
