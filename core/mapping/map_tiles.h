#pragma once

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "core/mapping/occupancy_grid.h"

namespace mobot::mapping {

// One square piece of a map on a fixed lattice of the map frame: tile (x, y) covers the cells
// whose lower-left corner lies at lattice origin + (x, y) * tile_cells * resolution. A map that
// grows (SLAM) keeps its tiles' places, so a viewer only needs the tiles that changed.
struct MapTile {
  std::int32_t x = 0;
  std::int32_t y = 0;
  std::vector<std::uint8_t> cells;  // tile_cells x tile_cells, row-major, row 0 at the bottom
};

struct MapTileUpdate {
  int tile_cells = 64;
  double resolution_m = 0.05;
  geometry::Pose2D lattice_origin;  // tile (0, 0)'s lower-left corner
  std::vector<MapTile> tiles;
};

// Cuts successive versions of a growing map into tiles and tells which changed since the last
// version. The grid must sit on the lattice: its origin a whole number of tiles from the lattice
// origin, unrotated (GraphSlam renders its maps so); cells outside the grid are unknown.
class MapTiler {
 public:
  explicit MapTiler(int tile_cells = 64, geometry::Pose2D lattice_origin = {});

  // The tiles of `grid` that differ from the previous call's (all non-unknown tiles the first
  // time). Throws std::invalid_argument when the grid is not on the lattice or its resolution
  // changed.
  MapTileUpdate changed_tiles(const OccupancyGrid& grid);
  std::size_t known_tiles() const { return tiles_.size(); }

 private:
  int tile_cells_;
  geometry::Pose2D lattice_origin_;
  double resolution_m_ = 0.0;
  std::map<std::pair<std::int32_t, std::int32_t>, std::vector<std::uint8_t>> tiles_;
};

}  // namespace mobot::mapping
