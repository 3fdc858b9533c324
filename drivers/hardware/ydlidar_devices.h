#pragma once

#include "drivers/hardware/hardware_assembly.h"

namespace mobot::drivers::hardware {

// laser: {driver: ydlidar_g4, device, baud: 230400, bins: 720, intensity: none|8|10}: the
// Dashgo's 360-degree lidar, on the profile's mount and range window.
void make_ydlidar_g4(DeviceReader& entry, HardwareAssembly& assembly);

}  // namespace mobot::drivers::hardware
