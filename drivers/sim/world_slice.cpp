#include "drivers/sim/world_slice.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "drivers/sim/oriented_rect.h"

namespace mobot::sim {

mapping::OccupancyGrid slice_at_height(const World& world, double z_m) {
  mapping::OccupancyGrid slice = world.floor;
  for (const Box3D& box : world.boxes) {
    if (box.min_z_m <= z_m && z_m <= box.max_z_m) rasterize_box(box, slice);
  }
  return slice;
}

void rasterize_box(const Box3D& box, mapping::OccupancyGrid& grid) {
  // Boxes usually sit on cell boundaries; shrinking them by a rounding error keeps a box that only
  // touches a row of cells from claiming it.
  const double slack_m = 1e-6 * grid.resolution_m();
  const AxisAlignedRect footprint{box.min_x_m + slack_m, box.min_y_m + slack_m,
                                  box.max_x_m - slack_m, box.max_y_m - slack_m};
  // The grid may be rotated: bound the box's corners in cell indices, then test each cell exactly.
  const std::array<geometry::Point2D, 4> corners = {{{box.min_x_m, box.min_y_m},
                                                     {box.max_x_m, box.min_y_m},
                                                     {box.min_x_m, box.max_y_m},
                                                     {box.max_x_m, box.max_y_m}}};
  mapping::CellIndex lo{grid.width(), grid.height()};
  mapping::CellIndex hi{-1, -1};
  for (const auto& corner : corners) {
    const mapping::CellIndex cell = grid.cell_at_unchecked(corner);
    lo = {std::min(lo.x, cell.x), std::min(lo.y, cell.y)};
    hi = {std::max(hi.x, cell.x), std::max(hi.y, cell.y)};
  }
  const double half_cell_m = grid.resolution_m() / 2.0;
  for (int y = std::max(lo.y, 0); y <= std::min(hi.y, grid.height() - 1); ++y) {
    for (int x = std::max(lo.x, 0); x <= std::min(hi.x, grid.width() - 1); ++x) {
      const geometry::Point2D center = grid.cell_center({x, y});
      const OrientedRect cell{{center.x, center.y, grid.origin().theta}, half_cell_m, half_cell_m};
      if (overlaps(cell, footprint)) grid.set({x, y}, mapping::OccupancyGrid::kOccupied);
    }
  }
}

}  // namespace mobot::sim
