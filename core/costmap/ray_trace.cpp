#include "core/costmap/ray_trace.h"

#include <algorithm>
#include <cmath>

namespace mobot::costmap {

std::optional<CellSegment> clip_to_grid(const planning::PlanningGrid& grid,
                                        geometry::Point2D from_map, geometry::Point2D to_map) {
  if (grid.empty() || !std::isfinite(from_map.x) || !std::isfinite(from_map.y) ||
      !std::isfinite(to_map.x) || !std::isfinite(to_map.y)) {
    return std::nullopt;
  }
  const geometry::Point2D a = grid.to_grid_frame_cells(from_map);
  const geometry::Point2D b = grid.to_grid_frame_cells(to_map);
  const double dx = b.x - a.x;
  const double dy = b.y - a.y;
  double t0 = 0.0;
  double t1 = 1.0;
  // Liang-Barsky: each side p t <= q of the box [0, width] x [0, height].
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {a.x, grid.width() - a.x, a.y, grid.height() - a.y};
  for (int side = 0; side < 4; ++side) {
    if (p[side] == 0.0) {
      if (q[side] < 0.0) return std::nullopt;
      continue;
    }
    const double t = q[side] / p[side];
    if (p[side] < 0.0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
    if (t0 > t1) return std::nullopt;
  }
  const auto cell = [&grid](double x, double y) {
    return mapping::CellIndex{std::clamp(static_cast<int>(std::floor(x)), 0, grid.width() - 1),
                              std::clamp(static_cast<int>(std::floor(y)), 0, grid.height() - 1)};
  };
  return CellSegment{cell(a.x + t0 * dx, a.y + t0 * dy), cell(a.x + t1 * dx, a.y + t1 * dy)};
}

}  // namespace mobot::costmap
