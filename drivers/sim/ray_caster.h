#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"

namespace mobot::sim {

// Casts rays through a fixed occupancy grid fast enough for a full laser scan every control tick.
// Occupied cells (OccupancyGrid::is_occupied) block; free and unknown cells do not, and nothing
// exists outside the grid, so a ray that leaves it has no return.
//
// In open space the caster sphere-traces: every cell stores how far a ray may jump from anywhere
// inside it without reaching a blocking cell (from a Euclidean distance transform), so crossing a
// 20 m room takes a handful of jumps instead of 400 cells. Near obstacles it walks cell by cell,
// so the hit lands exactly on the boundary of the first blocking cell, as a plain DDA would.
class RayCaster {
 public:
  explicit RayCaster(const mapping::OccupancyGrid& grid);

  // Distance from `from` along the map-frame heading `angle_rad` to where the ray enters the first
  // blocking cell, or nullopt when the ray leaves the grid or passes max_range_m first. A ray that
  // starts inside a blocking cell hits at 0.
  std::optional<double> cast(geometry::Point2D from, double angle_rad, double max_range_m) const;

  // A laser scan's fan: ray i leaves `from` at first_angle_rad + i * increment_rad, for every
  // element of ranges_m, which receives the distance or +infinity when there is no return.
  // Cheaper per ray than cast(): the direction is rotated rather than recomputed.
  void cast_fan(geometry::Point2D from, double first_angle_rad, double increment_rad,
                double max_range_m, std::span<double> ranges_m) const;

  // The same answer as cast() by visiting every cell on the way (Amanatides & Woo): the slow
  // reference that cast() is tested against.
  std::optional<double> cast_cell_by_cell(geometry::Point2D from, double angle_rad,
                                          double max_range_m) const;

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution_m() const { return resolution_m_; }

 private:
  struct Ray;
  class CellWalk;

  // The ray in grid units, clipped to the grid; false when it misses the grid within its range.
  bool to_grid(geometry::Point2D from, double grid_dir_x, double grid_dir_y, double max_range_m,
               Ray& ray) const;
  // Ray parameter (in cells) of the first blocking cell, or +infinity.
  double trace(const Ray& ray) const;
  double walk_every_cell(const Ray& ray) const;

  bool inside(int x, int y) const {
    return static_cast<unsigned>(x) < static_cast<unsigned>(width_) &&
           static_cast<unsigned>(y) < static_cast<unsigned>(height_);
  }
  std::size_t tile_index(int x, int y) const {
    return static_cast<std::size_t>((y >> kTileShift) * tiles_x_ + (x >> kTileShift));
  }
  // Cells are stored in 8 x 8 tiles of one cache line each, so walking along a wall touches few
  // lines.
  std::size_t cell_index(int x, int y) const {
    return (tile_index(x, y) << (2 * kTileShift)) |
           static_cast<std::size_t>(((y & kTileMask) << kTileShift) | (x & kTileMask));
  }
  std::uint8_t clearance_at(int x, int y) const { return clearance_[cell_index(x, y)]; }
  int tile_jump_at(int x, int y) const { return tile_jump_[tile_index(x, y)]; }

  static constexpr int kTileShift = 3;
  static constexpr int kTileMask = (1 << kTileShift) - 1;

  int width_ = 0;
  int height_ = 0;
  int tiles_x_ = 0;  // tiles per row, covering the grid and one more column of cells
  double resolution_m_ = 0.0;
  geometry::Pose2D origin_;
  double origin_cos_ = 1.0;
  double origin_sin_ = 0.0;
  // Per cell: 0 when it blocks, otherwise 1 + the whole number of cells a ray may advance from any
  // point of this cell without touching a blocking cell (saturated at 254).
  std::vector<std::uint8_t> clearance_;
  // Per tile: the shortest jump any of its cells allows. Open-space jumps read only this table,
  // which is 64 times smaller than the cells and stays in cache.
  std::vector<std::uint8_t> tile_jump_;
};

// Distance along the ray to the first point of a circle (0 when `from` lies inside it), or nullopt
// when the ray misses it. Dynamic obstacles are cylinders, so this is exact for them.
std::optional<double> cast_to_circle(geometry::Point2D from, double angle_rad,
                                     geometry::Point2D center, double radius_m);

}  // namespace mobot::sim
