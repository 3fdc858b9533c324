#pragma once

#include "drivers/hardware/hardware_assembly.h"

namespace mobot::drivers::hardware {

// pan_tilt: {driver: pololu_maestro, device, baud: 115200, pan_channel: 0, tilt_channel: 1,
// range_channel: 2 (-1: no ranger), pan_/tilt_centre_us: 1500, pan_/tilt_us_per_rad: 636.62,
// pan_/tilt_sign: 1, pan_min_deg: -90, pan_max_deg: 90, tilt_min_deg: -30, tilt_max_deg: 45,
// pan_/tilt_speed_dps (the profile's head rates), pan_/tilt_accel_dps2: 0, l0_m, l1_m, l2_m,
// mount_x_m (the profile's head), range_m_per_volt: 2.60096, range_max_m, range_cone_deg (the
// profile's ranger), rate_hz: 50, reply_timeout_ms: 25, crc: false}: R4's camera head on a Pololu
// Maestro (MaestroPanTilt), with its ultrasonic ranger (`head_range`). The camera it turns must be
// configured (hardware.camera, with its width and height): its description becomes a pan/tilt
// camera's.
void make_pololu_maestro(DeviceReader& entry, HardwareAssembly& assembly);

}  // namespace mobot::drivers::hardware
