#pragma once

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"

namespace mobot::perception {

// The 3D-obstacle layer of the planning map: what IPaBD derived from the sweeps, over the whole
// active map. A sweep overwrites the cells it observed (free or occupied) and leaves the rest, so
// an obstacle survives until a later sweep sees that area again.
class ObstacleLayer3D {
 public:
  // An empty layer (all unknown) over the map's extent, with cells of cell_m whose corners lie on
  // lattice_origin() (IpabdOptions::lattice_origin), so IPaBD results copy cell for cell.
  // Throws std::invalid_argument on an empty map or a non-positive cell.
  void reset(const mapping::OccupancyGrid& map, double cell_m);
  // Copies every observed cell of `observed` (an IPaBD grid on the same lattice and cell size)
  // that lies on the layer. Cells outside the layer are dropped. Returns the cells copied.
  int apply(const mapping::OccupancyGrid& observed);

  bool empty() const { return grid_.cells().empty(); }
  const mapping::OccupancyGrid& grid() const { return grid_; }
  geometry::Point2D lattice_origin() const { return {grid_.origin().x, grid_.origin().y}; }

 private:
  mapping::OccupancyGrid grid_;
};

}  // namespace mobot::perception
