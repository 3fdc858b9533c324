#include "core/costmap/grid_shift.h"

#include <algorithm>
#include <cstdlib>
#include <vector>

namespace mobot::costmap {

void shift_grid(planning::PlanningGrid& grid, int dx_cells, int dy_cells, std::uint8_t fill) {
  if (grid.empty() || (dx_cells == 0 && dy_cells == 0)) return;
  const int width = grid.width();
  const int height = grid.height();
  const geometry::Point2D new_corner = geometry::transform_point(
      grid.origin(), {dx_cells * grid.resolution_m(), dy_cells * grid.resolution_m()});
  planning::PlanningGrid shifted(width, height, grid.resolution_m(),
                                 {new_corner.x, new_corner.y, grid.origin().theta}, fill);
  // The overlap in new-grid cells: x in [x0, x1), y in [y0, y1).
  const int x0 = std::max(0, -dx_cells);
  const int x1 = std::min(width, width - dx_cells);
  const int y0 = std::max(0, -dy_cells);
  const int y1 = std::min(height, height - dy_cells);
  if (x0 < x1) {
    const std::vector<std::uint8_t>& from = grid.costs();
    std::vector<std::uint8_t>& to = shifted.mutable_costs();
    for (int y = y0; y < y1; ++y) {
      const auto source =
          from.begin() + static_cast<std::ptrdiff_t>(grid.index_of({x0 + dx_cells, y + dy_cells}));
      std::copy(source, source + (x1 - x0),
                to.begin() + static_cast<std::ptrdiff_t>(shifted.index_of({x0, y})));
    }
  }
  grid = std::move(shifted);
}

std::vector<CellBounds> entered_cells(int width_cells, int height_cells, int dx_cells,
                                      int dy_cells) {
  if (width_cells <= 0 || height_cells <= 0) return {};
  if (std::abs(dx_cells) >= width_cells || std::abs(dy_cells) >= height_cells) {
    return {CellBounds::of_size(width_cells, height_cells)};
  }
  std::vector<CellBounds> out;
  // Columns that entered, over the full height.
  if (dx_cells > 0) out.push_back({width_cells - dx_cells, 0, width_cells - 1, height_cells - 1});
  if (dx_cells < 0) out.push_back({0, 0, -dx_cells - 1, height_cells - 1});
  // Rows that entered, over the columns the first band does not hold.
  const int x0 = dx_cells < 0 ? -dx_cells : 0;
  const int x1 = dx_cells > 0 ? width_cells - dx_cells - 1 : width_cells - 1;
  if (dy_cells > 0 && x0 <= x1) out.push_back({x0, height_cells - dy_cells, x1, height_cells - 1});
  if (dy_cells < 0 && x0 <= x1) out.push_back({x0, 0, x1, -dy_cells - 1});
  return out;
}

bool same_geometry(const planning::PlanningGrid& a, const planning::PlanningGrid& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         a.resolution_m() == b.resolution_m() && a.origin() == b.origin();
}

}  // namespace mobot::costmap
