#pragma once

#include "drivers/hardware/hardware_assembly.h"

namespace mobot::drivers::hardware {

// base: {driver: dashgo_arduino, device, baud: 115200, kp, kd, ki, ko}: the base and its sonars.
void make_dashgo_arduino(DeviceReader& entry, HardwareAssembly& assembly);
// ir: {driver: sharp_ir_arduino, device, baud: 115200, pins: [0..9], rate_hz}: the IR ring.
void make_sharp_ir_arduino(DeviceReader& entry, HardwareAssembly& assembly);

}  // namespace mobot::drivers::hardware
