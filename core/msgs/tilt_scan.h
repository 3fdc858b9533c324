#pragma once

#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::msgs {

// One scan of the nodding laser (docs/algorithms.md R1, P1). Beam k points at bearing
// bearing_min_rad + k * bearing_step_rad in the scan plane, with bearing pi/2 straight ahead and 0
// to the right (the SICK convention P1 uses). The scan plane is pitched up by pitch_rad about the
// sensor's left-right axis. A range outside [range_min_m, range_max_m] means "no return".
struct TiltScan {
  double stamp_s = 0.0;
  // The pitch the scan is assigned. The hardware does not measure it: it is the scan count within
  // the sweep times delta_alpha (R1).
  double pitch_rad = 0.0;
  double bearing_min_rad = 0.0;
  double bearing_step_rad = 0.0;
  float range_min_m = 0.0F;
  float range_max_m = 0.0F;
  geometry::Pose2D sensor_in_base;  // the tilt axis' position and heading on the base
  double sensor_height_m = 0.0;     // the tilt axis above the floor
  std::vector<float> ranges_m;
  std::vector<float> intensities;  // one per range, 0..1
};

}  // namespace mobot::msgs
