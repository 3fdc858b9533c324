#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/costmap/costmap_layer.h"
#include "core/mapping/occupancy_grid.h"
#include "core/planning/planning_grid.h"

namespace mobot::costmap {

struct ObstacleGridLayerOptions {
  std::string name = "ipabd";
  // An occupancy value (0..100) at or above this is an obstacle.
  std::uint8_t occupied_threshold = mapping::OccupancyGrid::kOccupiedThreshold;
  // The heights the grid's source saw (the tilting laser's sweep sees the whole body height).
  HeightBand height_band{};
};

// Obstacle grids computed elsewhere, as extra lethal cells: the 2D projection of the 3D sweeps
// (IPaBD, docs/algorithms.md P2; perception::ObstacleLayer3D) or any other occupancy grid. The
// grids may have any resolution and origin: an occupied cell marks every master cell whose centre
// it covers, and the master cell under its own centre, so a finer grid is never lost. Free and
// unknown cells add nothing. Rasterised into its own grid in master cells; written by max.
class ObstacleGridLayer : public CostmapLayer {
 public:
  explicit ObstacleGridLayer(const ObstacleGridLayerOptions& options = {});

  std::string_view name() const override { return options_.name; }
  HeightBand height_band() const override { return options_.height_band; }

  // Replaces the grids; the whole master is recomputed at the next update.
  void set_grids(std::vector<mapping::OccupancyGrid> grids);
  void set_grid(const mapping::OccupancyGrid& grid) { set_grids({grid}); }
  const std::vector<mapping::OccupancyGrid>& grids() const { return sources_; }

  void match_geometry(const planning::PlanningGrid& master) override;
  void shift(const planning::PlanningGrid& master, int dx_cells, int dy_cells) override;
  void update_bounds(const planning::PlanningGrid& master, CellBounds& bounds) override;
  void update(planning::PlanningGrid& master, const CellBounds& bounds) override;

  // Sets to kLethal every cell of `target` within `bounds` that an occupied cell of `source`
  // marks (the rule above).
  static void rasterise(const mapping::OccupancyGrid& source, std::uint8_t occupied_threshold,
                        planning::PlanningGrid& target, const CellBounds& bounds);

 private:
  void rasterise_all(const CellBounds& bounds);

  ObstacleGridLayerOptions options_;
  std::vector<mapping::OccupancyGrid> sources_;
  planning::PlanningGrid grid_;
  bool changed_ = false;
};

}  // namespace mobot::costmap
