#pragma once

#include <span>
#include <string>

#include "core/perception/point_cloud.h"

namespace mobot::api {

// A cloud as a binary little-endian PLY (x, y, z, intensity as float), the format CloudCompare,
// MeshLab and Open3D read.
std::string encode_ply(std::span<const perception::CloudPoint> points);

}  // namespace mobot::api
