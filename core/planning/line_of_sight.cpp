#include "core/planning/line_of_sight.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace mobot::planning {
namespace {

// Per axis: the direction of the walk, the parameter t (0 at a, 1 at b) of the next cell
// boundary, and the t between boundaries (Amanatides & Woo).
struct AxisWalk {
  int step = 0;
  double t_next = std::numeric_limits<double>::infinity();
  double t_delta = std::numeric_limits<double>::infinity();
};

AxisWalk make_axis_walk(double from, double to, int cell) {
  AxisWalk walk;
  const double span = to - from;
  if (span > 0.0) {
    walk.step = 1;
    walk.t_delta = 1.0 / span;
    walk.t_next = (cell + 1 - from) / span;
  } else if (span < 0.0) {
    walk.step = -1;
    walk.t_delta = -1.0 / span;
    walk.t_next = (from - cell) / -span;
  }
  return walk;
}

}  // namespace

std::optional<std::uint8_t> max_cost_along_segment(const PlanningGrid& grid, geometry::Point2D a,
                                                   geometry::Point2D b) {
  const auto start = grid.cell_at(a);
  const auto end = grid.cell_at(b);
  if (!start || !end) return std::nullopt;
  const geometry::Point2D from = grid.to_grid_frame_cells(a);
  const geometry::Point2D to = grid.to_grid_frame_cells(b);

  mapping::CellIndex cell = *start;
  AxisWalk wx = make_axis_walk(from.x, to.x, cell.x);
  AxisWalk wy = make_axis_walk(from.y, to.y, cell.y);
  std::uint8_t highest = grid.cost(cell);
  const auto visit = [&](mapping::CellIndex c) {
    // The corner neighbours of an in-grid walk can only leave the grid at its border.
    if (grid.contains(c)) highest = std::max(highest, grid.cost(c));
  };
  // Cells still to enter; a corner crossing enters two at once.
  int remaining = std::abs(end->x - start->x) + std::abs(end->y - start->y);
  constexpr double kCornerTolerance = 1e-9;
  while (remaining > 0) {
    if (std::abs(wx.t_next - wy.t_next) < kCornerTolerance && remaining >= 2) {
      visit({cell.x + wx.step, cell.y});
      visit({cell.x, cell.y + wy.step});
      cell.x += wx.step;
      cell.y += wy.step;
      wx.t_next += wx.t_delta;
      wy.t_next += wy.t_delta;
      remaining -= 2;
    } else if (wx.t_next < wy.t_next) {
      cell.x += wx.step;
      wx.t_next += wx.t_delta;
      --remaining;
    } else {
      cell.y += wy.step;
      wy.t_next += wy.t_delta;
      --remaining;
    }
    visit(cell);
  }
  return highest;
}

bool segment_is_clear(const PlanningGrid& grid, geometry::Point2D a, geometry::Point2D b,
                      std::uint8_t max_cost) {
  const auto highest = max_cost_along_segment(grid, a, b);
  return highest && PlanningGrid::is_traversable_cost(*highest) && *highest <= max_cost;
}

}  // namespace mobot::planning
