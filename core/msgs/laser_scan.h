#pragma once

#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::msgs {

// One planar laser scan in the sensor frame. Beam i points at angle_min_rad + i *
// angle_increment_rad. A range outside [range_min_m, range_max_m] means "no return".
struct LaserScan {
  double stamp_s = 0.0;
  float angle_min_rad = 0.0F;
  float angle_increment_rad = 0.0F;
  float range_min_m = 0.0F;
  float range_max_m = 0.0F;
  geometry::Pose2D sensor_in_base;  // mounting pose of the sensor on the base
  std::vector<float> ranges_m;
};

}  // namespace mobot::msgs
