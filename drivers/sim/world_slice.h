#pragma once

#include "core/mapping/occupancy_grid.h"
#include "drivers/sim/world.h"

namespace mobot::sim {

// What a planar sensor at height z_m sees as obstacles: the floor plan's walls plus every box whose
// height range contains z_m, drawn in as occupied cells.
mapping::OccupancyGrid slice_at_height(const World& world, double z_m);

// Marks occupied every cell whose area overlaps the box's footprint (cells it only touches stay).
void rasterize_box(const Box3D& box, mapping::OccupancyGrid& grid);

}  // namespace mobot::sim
