#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "core/costmap/costmap_layer.h"
#include "core/mapping/occupancy_grid.h"
#include "core/planning/planning_grid.h"

namespace mobot::costmap {

struct StaticLayerOptions {
  std::string name = "static";
  // costmap_2d's track_unknown_space for the map: unknown cells stay kUnknown (they block and, by
  // default, inflate). False: they are free.
  bool unknown_is_obstacle = true;
  // An occupancy value (0..100) at or above this is lethal (ROS map_server's 0.65).
  std::uint8_t occupied_threshold = mapping::OccupancyGrid::kOccupiedThreshold;
};

// costmap_2d's static layer: the active map as costs (occupied -> kLethal, unknown -> kUnknown or
// kFree, the rest kFree), written first and by overwrite, so the sensor layers above it can only
// add. A master grid with the map's geometry is copied row by row; any other (a rolling window, a
// finer or rotated grid) samples the map cell under each master cell's centre, and master cells off
// the map keep the costmap's default.
class StaticLayer : public CostmapLayer {
 public:
  explicit StaticLayer(const StaticLayerOptions& options = {});

  std::string_view name() const override { return options_.name; }
  const StaticLayerOptions& options() const { return options_; }

  // Replaces the map; the whole master is recomputed at the next update.
  void set_map(const mapping::OccupancyGrid& map);
  bool has_map() const { return !map_costs_.empty(); }
  // The map as costs, in the map's own geometry.
  const planning::PlanningGrid& map_costs() const { return map_costs_; }
  std::uint8_t cost_of(std::uint8_t occupancy) const;

  void match_geometry(const planning::PlanningGrid& master) override;
  void shift(const planning::PlanningGrid& master, int dx_cells, int dy_cells) override;
  void update_bounds(const planning::PlanningGrid& master, CellBounds& bounds) override;
  void update(planning::PlanningGrid& master, const CellBounds& bounds) override;

 private:
  StaticLayerOptions options_;
  planning::PlanningGrid map_costs_;
  bool changed_ = false;
};

}  // namespace mobot::costmap
