#include "core/planning/planning_grid_builder.h"

#include <cmath>
#include <stdexcept>

#include "core/costmap/cell_bounds.h"
#include "core/costmap/keepout_layer.h"
#include "core/costmap/obstacle_grid_layer.h"
#include "core/costmap/static_layer.h"

namespace mobot::planning {
namespace {

bool is_valid_length(double value) { return std::isfinite(value) && value >= 0.0; }

const PlanningGridOptions& checked(const PlanningGridOptions& options) {
  if (!is_valid_length(options.inscribed_radius_m) ||
      !is_valid_length(options.inflation_margin_m) ||
      !is_valid_length(options.cost_scaling_per_m)) {
    throw std::invalid_argument("planning grid options must be finite and non-negative");
  }
  return options;
}

costmap::InflationLayerOptions inflation_options(const PlanningGridOptions& options) {
  costmap::InflationLayerOptions out;
  out.inscribed_radius_m = options.inscribed_radius_m;
  out.inflation_radius_m = options.inscribed_radius_m + options.inflation_margin_m;
  out.cost_scaling_per_m = options.cost_scaling_per_m;
  out.inflate_unknown = options.unknown_is_obstacle;
  return out;
}

}  // namespace

PlanningGridBuilder::PlanningGridBuilder(const PlanningGridOptions& options)
    : options_(checked(options)), inflation_(inflation_options(options)) {}

PlanningGrid PlanningGridBuilder::build(const mapping::OccupancyGrid& occupancy,
                                        const ExtraObstacles& extra) const {
  if (occupancy.width() <= 0 || occupancy.height() <= 0 || occupancy.cells().empty()) return {};
  costmap::StaticLayerOptions static_options;
  static_options.unknown_is_obstacle = options_.unknown_is_obstacle;
  static_options.occupied_threshold = options_.occupied_threshold;
  costmap::StaticLayer static_layer(static_options);
  static_layer.set_map(occupancy);
  // The grid has the map's geometry: the static layer's costs are its first layer as they are.
  PlanningGrid grid = static_layer.map_costs();
  const costmap::CellBounds all = costmap::CellBounds::of_size(grid.width(), grid.height());

  // Extra obstacles are lethal even where the map is unknown (max combination over kUnknown).
  for (const mapping::OccupancyGrid& extra_grid : extra.grids) {
    costmap::ObstacleGridLayer::rasterise(extra_grid, mapping::OccupancyGrid::kOccupiedThreshold,
                                          grid, all);
  }
  for (const geometry::Point2D& point : extra.points_in_map) {
    if (const auto cell = grid.cell_at(point)) grid.set_cost(*cell, PlanningGrid::kLethal);
  }
  if (!extra.keepout_zones.empty()) {
    costmap::KeepoutLayer keepout;
    const std::vector<std::vector<geometry::Point2D>> zones(extra.keepout_zones.begin(),
                                                            extra.keepout_zones.end());
    if (const auto refused = keepout.set_zones(zones)) throw std::invalid_argument(*refused);
    keepout.match_geometry(grid);
    costmap::CellBounds bounds = all;
    keepout.update_bounds(grid, bounds);
    keepout.update(grid, all);
  }

  // A layer per build: its scratch buffers make inflate() non-const, and build() may run on
  // several threads.
  costmap::InflationLayer inflation(inflation_.options());
  inflation.inflate(grid, all);
  return grid;
}

}  // namespace mobot::planning
