#pragma once

#include <optional>

#include "core/geometry/pose2d.h"

namespace mobot::emulate {

// What the emulated devices of one robot share: where the base truly is (the emulated base
// integrates its wheel speeds into it) and the floor plan its range sensors see. The base writes
// the pose, the sensors read it; one emulator thread runs them all, so no locking.
class EmulatedWorld {
 public:
  virtual ~EmulatedWorld() = default;

  virtual geometry::Pose2D base_pose() const = 0;
  virtual void set_base_pose(const geometry::Pose2D& pose) = 0;
  // Distance from `from` (map frame, metres) along the map-frame heading `angle_rad` to the
  // first surface at `height_m` above the floor, or nullopt when nothing is within max_range_m.
  virtual std::optional<double> cast_ray(geometry::Point2D from, double angle_rad, double height_m,
                                         double max_range_m) const = 0;
};

}  // namespace mobot::emulate
