#pragma once

#include "core/geometry/pose2d.h"

namespace mobot::sim {

// A rectangle centred on `center` and turned by center.theta: the robot's footprint, or a grid cell
// of a map whose origin is rotated.
struct OrientedRect {
  geometry::Pose2D center;
  double half_length_m = 0.0;  // along center.theta
  double half_width_m = 0.0;
};

struct AxisAlignedRect {
  double min_x_m = 0.0;
  double min_y_m = 0.0;
  double max_x_m = 0.0;
  double max_y_m = 0.0;
};

// True when the interiors overlap; touching edges do not count, so a robot may stand flush
// against a wall.
bool overlaps(const OrientedRect& rect, const AxisAlignedRect& box);
bool overlaps_circle(const OrientedRect& rect, geometry::Point2D center, double radius_m);

// The smallest axis-aligned rectangle holding `rect`.
AxisAlignedRect bounding_box(const OrientedRect& rect);

}  // namespace mobot::sim
