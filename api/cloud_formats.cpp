#include "api/cloud_formats.h"

#include <bit>

namespace mobot::api {

std::string encode_ply(std::span<const perception::CloudPoint> points) {
  static_assert(std::endian::native == std::endian::little);
  static_assert(sizeof(perception::CloudPoint) == 16);
  std::string out =
      "ply\nformat binary_little_endian 1.0\ncomment mobot 3D sweep, map frame, metres\n"
      "element vertex " +
      std::to_string(points.size()) +
      "\nproperty float x\nproperty float y\nproperty float z\nproperty float intensity\n"
      "end_header\n";
  out.append(reinterpret_cast<const char*>(points.data()),
             points.size() * sizeof(perception::CloudPoint));
  return out;
}

}  // namespace mobot::api
