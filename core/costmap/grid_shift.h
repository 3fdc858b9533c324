#pragma once

#include <cstdint>
#include <vector>

#include "core/costmap/cell_bounds.h"
#include "core/planning/planning_grid.h"

namespace mobot::costmap {

// costmap_2d's updateOrigin: moves the grid's origin by whole cells along its own axes, keeping
// the cells both windows share (new cell (x, y) is old cell (x + dx_cells, y + dy_cells)) and
// filling the cells that enter with `fill`. Nothing is recomputed.
void shift_grid(planning::PlanningGrid& grid, int dx_cells, int dy_cells, std::uint8_t fill);

// The cells of a width x height grid that entered it with a shift_grid(dx_cells, dy_cells): at most
// two rectangles (a column band and a row band, not overlapping); all of it when the shift is at
// least the grid's size.
std::vector<CellBounds> entered_cells(int width_cells, int height_cells, int dx_cells,
                                      int dy_cells);

// Same size, resolution and origin: cell (x, y) of one is cell (x, y) of the other.
bool same_geometry(const planning::PlanningGrid& a, const planning::PlanningGrid& b);

}  // namespace mobot::costmap
