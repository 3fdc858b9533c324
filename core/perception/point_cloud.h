#pragma once

#include <vector>

namespace mobot::perception {

// One point of a 3D cloud in the map frame: metres, z up from the floor. float keeps a 72 000-point
// sweep at 1.1 MB and is what the stream and the PLY files carry.
struct CloudPoint {
  float x_m = 0.0F;
  float y_m = 0.0F;
  float z_m = 0.0F;
  float intensity = 0.0F;  // 0..1, the sensor's reflectance reading
};

using PointCloud = std::vector<CloudPoint>;

}  // namespace mobot::perception
