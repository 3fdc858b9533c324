#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::msgs {

// A landmark seen by the omnidirectional camera: its bearing in the base frame (radians CCW from
// the robot's heading) and the landmark's known map position.
struct LandmarkBearing {
  std::string name;
  geometry::Point2D landmark_in_map;
  double bearing_rad = 0.0;
  // The distance to the landmark's centre, from a sensor that measures one (the tricycles' beacon
  // scanner, docs/algorithms.md E3); the omnidirectional camera gives none.
  std::optional<double> range_m;
};

// Every landmark the camera saw in one image, in no particular order of importance.
struct LandmarkBearings {
  double stamp_s = 0.0;
  std::vector<LandmarkBearing> bearings;
};

}  // namespace mobot::msgs
