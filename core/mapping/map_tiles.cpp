#include "core/mapping/map_tiles.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace mobot::mapping {
namespace {

// Whole tiles from the lattice origin to `offset_m`; nothing when it is not a whole number.
std::optional<std::int32_t> whole_tiles(double offset_m, double tile_m) {
  const double tiles = offset_m / tile_m;
  const double rounded = std::round(tiles);
  if (std::abs(tiles - rounded) > 1e-6) return std::nullopt;
  return static_cast<std::int32_t>(rounded);
}

}  // namespace

MapTiler::MapTiler(int tile_cells, geometry::Pose2D lattice_origin)
    : tile_cells_(tile_cells), lattice_origin_(lattice_origin) {
  if (tile_cells <= 0) throw std::invalid_argument("tile_cells must be positive");
}

MapTileUpdate MapTiler::changed_tiles(const OccupancyGrid& grid) {
  MapTileUpdate update;
  update.tile_cells = tile_cells_;
  update.resolution_m = grid.resolution_m();
  update.lattice_origin = lattice_origin_;
  if (grid.width() == 0 || grid.height() == 0) return update;
  if (resolution_m_ != 0.0 && std::abs(resolution_m_ - grid.resolution_m()) > 1e-12) {
    throw std::invalid_argument("the map's resolution changed between versions");
  }
  resolution_m_ = grid.resolution_m();
  const double tile_m = tile_cells_ * grid.resolution_m();
  const auto first_x = whole_tiles(grid.origin().x - lattice_origin_.x, tile_m);
  const auto first_y = whole_tiles(grid.origin().y - lattice_origin_.y, tile_m);
  if (!first_x || !first_y || std::abs(grid.origin().theta - lattice_origin_.theta) > 1e-9) {
    throw std::invalid_argument("the map does not sit on the tile lattice");
  }
  const int tiles_x = (grid.width() + tile_cells_ - 1) / tile_cells_;
  const int tiles_y = (grid.height() + tile_cells_ - 1) / tile_cells_;
  const auto side = static_cast<std::size_t>(tile_cells_);
  std::vector<std::uint8_t> cells(side * side);
  for (int ty = 0; ty < tiles_y; ++ty) {
    for (int tx = 0; tx < tiles_x; ++tx) {
      std::fill(cells.begin(), cells.end(), OccupancyGrid::kUnknown);
      bool any_known = false;
      for (int row = 0; row < tile_cells_; ++row) {
        const int y = ty * tile_cells_ + row;
        if (y >= grid.height()) break;
        for (int col = 0; col < tile_cells_; ++col) {
          const int x = tx * tile_cells_ + col;
          if (x >= grid.width()) break;
          const std::uint8_t value = grid.at({x, y});
          cells[static_cast<std::size_t>(row) * side + static_cast<std::size_t>(col)] = value;
          any_known = any_known || value != OccupancyGrid::kUnknown;
        }
      }
      const std::pair<std::int32_t, std::int32_t> key{*first_x + tx, *first_y + ty};
      const auto known = tiles_.find(key);
      if (known == tiles_.end() ? !any_known : known->second == cells) continue;
      tiles_[key] = cells;
      update.tiles.push_back({key.first, key.second, cells});
    }
  }
  return update;
}

}  // namespace mobot::mapping
