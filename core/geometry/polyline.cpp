#include "core/geometry/polyline.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mobot::geometry {

double distance_to_polyline(const std::vector<Point2D>& vertices, Point2D point) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < vertices.size(); ++i) {
    const double dx = vertices[i + 1].x - vertices[i].x;
    const double dy = vertices[i + 1].y - vertices[i].y;
    const double length2 = dx * dx + dy * dy;
    const double along =
        length2 > 0.0 ? ((point.x - vertices[i].x) * dx + (point.y - vertices[i].y) * dy) / length2
                      : 0.0;
    const double f = std::clamp(along, 0.0, 1.0);
    best = std::min(best,
                    std::hypot(vertices[i].x + f * dx - point.x, vertices[i].y + f * dy - point.y));
  }
  return best;
}

}  // namespace mobot::geometry
