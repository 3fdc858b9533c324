#include "core/costmap/static_layer.h"

#include <algorithm>
#include <cmath>

#include "core/costmap/cost_combination.h"
#include "core/costmap/grid_shift.h"

namespace mobot::costmap {
namespace {

using planning::PlanningGrid;

// Master cell (x, y) is map cell (x + dx, y + dy) for whole dx, dy: same resolution and rotation,
// origins a whole number of cells apart (a rolling window on the map's lattice).
bool aligned_offset(const PlanningGrid& master, const PlanningGrid& map, int& dx, int& dy) {
  if (master.resolution_m() != map.resolution_m() || master.origin().theta != map.origin().theta) {
    return false;
  }
  const geometry::Point2D offset = map.to_grid_frame_cells({master.origin().x, master.origin().y});
  const double rx = std::round(offset.x);
  const double ry = std::round(offset.y);
  if (std::abs(offset.x - rx) > 1e-6 || std::abs(offset.y - ry) > 1e-6 || std::abs(rx) > 1e9 ||
      std::abs(ry) > 1e9) {
    return false;
  }
  dx = static_cast<int>(rx);
  dy = static_cast<int>(ry);
  return true;
}

}  // namespace

StaticLayer::StaticLayer(const StaticLayerOptions& options) : options_(options) {}

std::uint8_t StaticLayer::cost_of(std::uint8_t occupancy) const {
  if (occupancy == mapping::OccupancyGrid::kUnknown) {
    return options_.unknown_is_obstacle ? PlanningGrid::kUnknown : PlanningGrid::kFree;
  }
  return occupancy >= options_.occupied_threshold ? PlanningGrid::kLethal : PlanningGrid::kFree;
}

void StaticLayer::set_map(const mapping::OccupancyGrid& map) {
  changed_ = true;
  if (map.width() <= 0 || map.height() <= 0 || map.cells().empty()) {
    map_costs_ = {};
    return;
  }
  map_costs_ = PlanningGrid(map.width(), map.height(), map.resolution_m(), map.origin());
  // A table, not a branch per cell: the conversion runs over every cell of a large map.
  std::uint8_t table[256];
  for (int value = 0; value < 256; ++value)
    table[value] = cost_of(static_cast<std::uint8_t>(value));
  std::transform(map.cells().begin(), map.cells().end(), map_costs_.mutable_costs().begin(),
                 [&table](std::uint8_t value) { return table[value]; });
}

void StaticLayer::match_geometry(const PlanningGrid& /*master*/) { changed_ = true; }

void StaticLayer::shift(const PlanningGrid& /*master*/, int /*dx_cells*/, int /*dy_cells*/) {}

void StaticLayer::update_bounds(const PlanningGrid& master, CellBounds& bounds) {
  if (!changed_) return;
  bounds.include(CellBounds::of_size(master.width(), master.height()));
  changed_ = false;
}

void StaticLayer::update(PlanningGrid& master, const CellBounds& bounds) {
  if (map_costs_.empty()) return;
  if (same_geometry(master, map_costs_)) {
    write_overwrite(map_costs_, master, bounds);
    return;
  }
  std::vector<std::uint8_t>& out = master.mutable_costs();
  const std::vector<std::uint8_t>& in = map_costs_.costs();
  int dx = 0;
  int dy = 0;
  if (aligned_offset(master, map_costs_, dx, dy)) {
    // Rows of the bounds that fall on the map, copied in one piece each.
    const int x0 = std::max(bounds.min_x, -dx);
    const int x1 = std::min(bounds.max_x, map_costs_.width() - 1 - dx);
    const int y0 = std::max(bounds.min_y, -dy);
    const int y1 = std::min(bounds.max_y, map_costs_.height() - 1 - dy);
    for (int y = y0; y <= y1 && x0 <= x1; ++y) {
      const auto from =
          in.begin() + static_cast<std::ptrdiff_t>(map_costs_.index_of({x0 + dx, y + dy}));
      std::copy(from, from + (x1 - x0 + 1),
                out.begin() + static_cast<std::ptrdiff_t>(master.index_of({x0, y})));
    }
    return;
  }
  for (int y = bounds.min_y; y <= bounds.max_y; ++y) {
    for (int x = bounds.min_x; x <= bounds.max_x; ++x) {
      if (const auto cell = map_costs_.cell_at(master.cell_center({x, y}))) {
        out[master.index_of({x, y})] = in[map_costs_.index_of(*cell)];
      }
    }
  }
}

}  // namespace mobot::costmap
