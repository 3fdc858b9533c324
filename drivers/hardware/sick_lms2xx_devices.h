#pragma once

#include "drivers/hardware/hardware_assembly.h"

namespace mobot::drivers::hardware {

// laser: {driver: sick_lms2xx, device, baud: 38400 | 500000 (38400), resolution_deg: 0.25 | 0.5
// | 1 (0.5)}: the SICK LMS 200/211/291 over 180 deg, at the profile's laser mount and ranges.
// 0.25 deg needs 500000 baud. The laser's scans are also the assembly's laser_source.
void make_sick_lms2xx(DeviceReader& entry, HardwareAssembly& assembly);

}  // namespace mobot::drivers::hardware
