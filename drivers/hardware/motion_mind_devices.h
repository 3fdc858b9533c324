#pragma once

#include "drivers/hardware/hardware_assembly.h"

namespace mobot::drivers::hardware {

// base: {driver: motion_mind, device, baud: 19200, left_address: 1, right_address: 2,
// left_sign: 1, right_sign: 1}: R1's wheels, a Motion Mind 3 board each on one line (a sign of -1
// for a mirrored motor). The line is shared with the tilt (assembly.shared_lines).
void make_motion_mind_base(DeviceReader& entry, HardwareAssembly& assembly);
// tilt: {driver: motion_mind, address: 3, counts_per_degree, device, baud: 19200, home_speed_dps:
// 10}: the nodding laser's tilt axis, on the base's line when `device` is absent or the base's,
// else on a line of its own; its scans come from the laser (hardware.laser is required).
void make_motion_mind_tilt(DeviceReader& entry, HardwareAssembly& assembly);

}  // namespace mobot::drivers::hardware
