#pragma once

#include <algorithm>
#include <cstddef>

#include "core/mapping/occupancy_grid.h"

namespace mobot::costmap {

// An axis-aligned rectangle of grid cells, inclusive on both ends: what a costmap layer changed and
// what the master grid recomputes (costmap_2d's update bounds, in cells). Default: empty.
struct CellBounds {
  int min_x = 0;
  int min_y = 0;
  int max_x = -1;
  int max_y = -1;

  static CellBounds of_size(int width_cells, int height_cells) {
    return {0, 0, width_cells - 1, height_cells - 1};
  }
  static CellBounds of_cell(mapping::CellIndex cell) { return {cell.x, cell.y, cell.x, cell.y}; }

  bool empty() const { return max_x < min_x || max_y < min_y; }
  int width() const { return empty() ? 0 : max_x - min_x + 1; }
  int height() const { return empty() ? 0 : max_y - min_y + 1; }
  std::size_t cell_count() const {
    return static_cast<std::size_t>(width()) * static_cast<std::size_t>(height());
  }
  bool contains(mapping::CellIndex cell) const {
    return cell.x >= min_x && cell.x <= max_x && cell.y >= min_y && cell.y <= max_y;
  }

  void include(mapping::CellIndex cell) { include(of_cell(cell)); }
  void include(const CellBounds& other) {
    if (other.empty()) return;
    if (empty()) {
      *this = other;
      return;
    }
    min_x = std::min(min_x, other.min_x);
    min_y = std::min(min_y, other.min_y);
    max_x = std::max(max_x, other.max_x);
    max_y = std::max(max_y, other.max_y);
  }
  // Grown by `cells` on every side (an empty rectangle stays empty).
  CellBounds expanded(int cells) const {
    if (empty()) return {};
    return {min_x - cells, min_y - cells, max_x + cells, max_y + cells};
  }
  CellBounds intersected(const CellBounds& other) const {
    if (empty() || other.empty()) return {};
    const CellBounds out{std::max(min_x, other.min_x), std::max(min_y, other.min_y),
                         std::min(max_x, other.max_x), std::min(max_y, other.max_y)};
    return out.empty() ? CellBounds{} : out;
  }
  CellBounds clipped(int width_cells, int height_cells) const {
    return intersected(of_size(width_cells, height_cells));
  }

  bool operator==(const CellBounds&) const = default;
};

}  // namespace mobot::costmap
