#include "core/planning/planning_grid.h"

#include <cmath>
#include <stdexcept>

namespace mobot::planning {

PlanningGrid::PlanningGrid(int width_cells, int height_cells, double resolution_m,
                           geometry::Pose2D origin, std::uint8_t fill)
    : width_(width_cells), height_(height_cells), resolution_m_(resolution_m), origin_(origin) {
  if (width_cells <= 0 || height_cells <= 0) {
    throw std::invalid_argument("planning grid needs a positive width and height");
  }
  if (!(resolution_m > 0.0) || !std::isfinite(resolution_m)) {
    throw std::invalid_argument("planning grid needs a positive finite resolution");
  }
  costs_.assign(static_cast<std::size_t>(width_cells) * static_cast<std::size_t>(height_cells),
                fill);
}

geometry::Point2D PlanningGrid::to_grid_frame_cells(geometry::Point2D point_in_map) const {
  const geometry::Point2D local =
      geometry::transform_point(geometry::inverse(origin_), point_in_map);
  return {local.x / resolution_m_, local.y / resolution_m_};
}

std::optional<mapping::CellIndex> PlanningGrid::cell_at(geometry::Point2D point_in_map) const {
  if (!std::isfinite(point_in_map.x) || !std::isfinite(point_in_map.y) || empty()) {
    return std::nullopt;
  }
  const geometry::Point2D local = to_grid_frame_cells(point_in_map);
  // Compare in floating point first: a far-away point must not overflow the int conversion.
  if (local.x < 0.0 || local.y < 0.0 || local.x >= width_ || local.y >= height_) {
    return std::nullopt;
  }
  const mapping::CellIndex cell{static_cast<int>(local.x), static_cast<int>(local.y)};
  if (!contains(cell)) return std::nullopt;
  return cell;
}

geometry::Point2D PlanningGrid::cell_center(mapping::CellIndex cell) const {
  const geometry::Point2D local{(cell.x + 0.5) * resolution_m_, (cell.y + 0.5) * resolution_m_};
  return geometry::transform_point(origin_, local);
}

}  // namespace mobot::planning
