#pragma once

#include <vector>

#include "core/geometry/pose2d.h"

namespace mobot::geometry {

// The shortest distance from `point` to the polyline through `vertices`; infinity when it has
// fewer than two vertices.
double distance_to_polyline(const std::vector<Point2D>& vertices, Point2D point);

}  // namespace mobot::geometry
