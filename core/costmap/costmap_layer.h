#pragma once

#include <limits>
#include <string_view>

#include "core/costmap/cell_bounds.h"
#include "core/planning/planning_grid.h"

namespace mobot::costmap {

// The band of heights above the floor a layer's sensors observe. It is what a layer may clear:
// the lidar's plane never sees a table top that only the IR ring marked, so each sensor keeps its
// own layer grid and the master combines them by max (docs/algorithms.md P3).
struct HeightBand {
  double min_z_m = -std::numeric_limits<double>::infinity();
  double max_z_m = std::numeric_limits<double>::infinity();

  bool operator==(const HeightBand&) const = default;
};

// One layer of a LayeredCostmap, as in costmap_2d: the layer keeps what it knows (a map, its own
// grid of observations, polygons), says which master cells it changed, and writes its costs into
// the master grid over the bounds the costmap recomputes. The master is a planning::PlanningGrid
// with costmap_2d's values.
//
// The costmap calls, per update: update_bounds() on every layer in order (a layer includes the
// cells it changed; the inflation layer, last, grows the bounds by its radius), then resets the
// bounds in the master to its default cost and calls update() on every layer in order.
class CostmapLayer {
 public:
  virtual ~CostmapLayer() = default;

  virtual std::string_view name() const = 0;
  virtual HeightBand height_band() const { return {}; }

  // The master grid was given a new geometry (a new static map, the first rolling window): the
  // layer drops or rebuilds what it keeps per master cell. Everything is recomputed next update.
  virtual void match_geometry(const planning::PlanningGrid& master) = 0;
  // The rolling window moved by whole cells: master cell (x, y) is now what was cell
  // (x + dx_cells, y + dy_cells). `master` already has its new origin. The costmap recomputes the
  // cells that entered the window itself.
  virtual void shift(const planning::PlanningGrid& master, int dx_cells, int dy_cells) = 0;
  // Folds what arrived since the last update into the layer and includes the master cells whose
  // cost from this layer may have changed in `bounds`.
  virtual void update_bounds(const planning::PlanningGrid& master, CellBounds& bounds) = 0;
  // Writes this layer's costs into `master` over `bounds` (inside the grid, not empty).
  virtual void update(planning::PlanningGrid& master, const CellBounds& bounds) = 0;
};

}  // namespace mobot::costmap
