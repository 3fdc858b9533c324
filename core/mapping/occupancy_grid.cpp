#include "core/mapping/occupancy_grid.h"

#include <cmath>
#include <stdexcept>

namespace mobot::mapping {

OccupancyGrid::OccupancyGrid(int width_cells, int height_cells, double resolution_m,
                             geometry::Pose2D origin, std::uint8_t fill)
    : width_(width_cells), height_(height_cells), resolution_m_(resolution_m), origin_(origin) {
  if (width_cells <= 0 || height_cells <= 0) {
    throw std::invalid_argument("occupancy grid needs a positive width and height");
  }
  if (!(resolution_m > 0.0) || !std::isfinite(resolution_m)) {
    throw std::invalid_argument("occupancy grid needs a positive finite resolution");
  }
  cells_.assign(static_cast<std::size_t>(width_cells) * static_cast<std::size_t>(height_cells),
                fill);
}

CellIndex OccupancyGrid::cell_at_unchecked(geometry::Point2D point_in_map) const {
  const geometry::Point2D local =
      geometry::transform_point(geometry::inverse(origin_), point_in_map);
  return {static_cast<int>(std::floor(local.x / resolution_m_)),
          static_cast<int>(std::floor(local.y / resolution_m_))};
}

std::optional<CellIndex> OccupancyGrid::cell_at(geometry::Point2D point_in_map) const {
  const CellIndex cell = cell_at_unchecked(point_in_map);
  if (!contains(cell)) return std::nullopt;
  return cell;
}

geometry::Point2D OccupancyGrid::cell_center(CellIndex cell) const {
  const geometry::Point2D local{(cell.x + 0.5) * resolution_m_, (cell.y + 0.5) * resolution_m_};
  return geometry::transform_point(origin_, local);
}

}  // namespace mobot::mapping
