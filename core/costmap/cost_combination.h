#pragma once

#include <cstdint>

#include "core/costmap/cell_bounds.h"
#include "core/planning/planning_grid.h"

namespace mobot::costmap {

// costmap_2d's updateWithMax for one cell: a layer's kUnknown means "no information" and leaves the
// master alone; an unknown master cell takes the layer's value; otherwise the higher cost wins.
inline void combine_max(std::uint8_t layer_cost, std::uint8_t& master_cost) {
  if (layer_cost == planning::PlanningGrid::kUnknown) return;
  if (master_cost == planning::PlanningGrid::kUnknown || layer_cost > master_cost) {
    master_cost = layer_cost;
  }
}

// combine_max over `bounds` of two grids of the same size (a layer's own grid and the master).
void write_max(const planning::PlanningGrid& layer, planning::PlanningGrid& master,
               const CellBounds& bounds);

// costmap_2d's updateWithTrueOverwrite: the layer's values, unknown included, replace the
// master's over `bounds` (the static layer, which writes first).
void write_overwrite(const planning::PlanningGrid& layer, planning::PlanningGrid& master,
                     const CellBounds& bounds);

}  // namespace mobot::costmap
