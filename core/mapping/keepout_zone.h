#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::mapping {

// An area of a map the robot must never enter (a staircase, a wet floor), drawn by a user: a
// simple polygon in the map's frame. Planning treats its inside as lethal.
struct KeepoutZone {
  std::int64_t id = 0;
  std::string name;
  std::vector<geometry::Point2D> polygon;
};

}  // namespace mobot::mapping
