#include "core/planning/path_smoother.h"

#include <cmath>
#include <stdexcept>

#include "core/planning/line_of_sight.h"

namespace mobot::planning {

PathSmoother::PathSmoother(const PathSmootherOptions& options) : options_(options) {
  if (!std::isfinite(options.waypoint_spacing_m) || options.waypoint_spacing_m < 0.0) {
    throw std::invalid_argument("waypoint spacing must be finite and non-negative");
  }
}

std::vector<geometry::Point2D> PathSmoother::smooth(
    const PlanningGrid& grid, const std::vector<geometry::Point2D>& points) const {
  const std::vector<geometry::Point2D> pulled = shortcut(grid, points);
  if (options_.waypoint_spacing_m <= 0.0) return pulled;
  return densify(pulled, options_.waypoint_spacing_m);
}

std::vector<geometry::Point2D> PathSmoother::shortcut(
    const PlanningGrid& grid, const std::vector<geometry::Point2D>& points) const {
  if (points.size() <= 2) return points;
  std::vector<geometry::Point2D> out{points.front()};
  std::size_t anchor = 0;
  while (anchor + 1 < points.size()) {
    // Greedy: extend the shortcut until the first point that is not visible. Stopping at the first
    // failure keeps the work linear in the path length times the shortcut length.
    std::size_t reach = anchor + 1;
    for (std::size_t j = anchor + 2; j < points.size(); ++j) {
      if (!segment_is_clear(grid, points[anchor], points[j], options_.max_shortcut_cost)) break;
      reach = j;
    }
    out.push_back(points[reach]);
    anchor = reach;
  }
  return out;
}

std::vector<geometry::Point2D> PathSmoother::densify(const std::vector<geometry::Point2D>& points,
                                                     double spacing_m) {
  if (points.size() < 2 || !(spacing_m > 0.0)) return points;
  std::vector<geometry::Point2D> out{points.front()};
  for (std::size_t i = 1; i < points.size(); ++i) {
    const geometry::Point2D& a = points[i - 1];
    const geometry::Point2D& b = points[i];
    const double length = std::hypot(b.x - a.x, b.y - a.y);
    const auto pieces = static_cast<int>(std::ceil(length / spacing_m - 1e-9));
    for (int k = 1; k < pieces; ++k) {
      const double t = static_cast<double>(k) / pieces;
      out.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
    }
    out.push_back(b);
  }
  return out;
}

}  // namespace mobot::planning
