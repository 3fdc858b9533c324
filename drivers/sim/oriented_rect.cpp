#include "drivers/sim/oriented_rect.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace mobot::sim {
namespace {

struct Interval {
  double lo = 0.0;
  double hi = 0.0;
};

bool interiors_overlap(Interval a, Interval b) { return a.lo < b.hi && b.lo < a.hi; }

// Projection of the rectangle, turned by the angle with cosine c and sine s, onto the unit axis
// (axis_x, axis_y).
Interval project(const OrientedRect& rect, double c, double s, double axis_x, double axis_y) {
  const double middle = rect.center.x * axis_x + rect.center.y * axis_y;
  const double reach = rect.half_length_m * std::abs(c * axis_x + s * axis_y) +
                       rect.half_width_m * std::abs(-s * axis_x + c * axis_y);
  return {middle - reach, middle + reach};
}

Interval project(const AxisAlignedRect& box, double axis_x, double axis_y) {
  const double a = box.min_x_m * axis_x;
  const double b = box.max_x_m * axis_x;
  const double c = box.min_y_m * axis_y;
  const double d = box.max_y_m * axis_y;
  return {std::min(a, b) + std::min(c, d), std::max(a, b) + std::max(c, d)};
}

}  // namespace

bool overlaps(const OrientedRect& rect, const AxisAlignedRect& box) {
  // Separating axis theorem: two convex boxes are disjoint iff one of their four edge normals
  // separates them.
  const double c = std::cos(rect.center.theta);
  const double s = std::sin(rect.center.theta);
  const std::array<std::array<double, 2>, 4> axes = {{{1.0, 0.0}, {0.0, 1.0}, {c, s}, {-s, c}}};
  for (const auto& axis : axes) {
    if (!interiors_overlap(project(rect, c, s, axis[0], axis[1]), project(box, axis[0], axis[1]))) {
      return false;
    }
  }
  return true;
}

bool overlaps_circle(const OrientedRect& rect, geometry::Point2D center, double radius_m) {
  const geometry::Point2D local = geometry::transform_point(geometry::inverse(rect.center), center);
  const double nearest_x = std::clamp(local.x, -rect.half_length_m, rect.half_length_m);
  const double nearest_y = std::clamp(local.y, -rect.half_width_m, rect.half_width_m);
  return std::hypot(local.x - nearest_x, local.y - nearest_y) < radius_m;
}

AxisAlignedRect bounding_box(const OrientedRect& rect) {
  const double c = std::cos(rect.center.theta);
  const double s = std::sin(rect.center.theta);
  const Interval x = project(rect, c, s, 1.0, 0.0);
  const Interval y = project(rect, c, s, 0.0, 1.0);
  return {x.lo, y.lo, x.hi, y.hi};
}

}  // namespace mobot::sim
