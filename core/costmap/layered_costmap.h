#pragma once

#include <memory>
#include <string_view>
#include <vector>

#include "core/costmap/cell_bounds.h"
#include "core/costmap/costmap_layer.h"
#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "core/planning/planning_grid.h"

namespace mobot::costmap {

struct LayeredCostmapOptions {
  // false: a global costmap, sized to the static map by resize_to(). true: a window of
  // width_m x height_m centred on the robot that moves with it (the Dashgo thesis's 3 x 3 m local
  // costmap at 0.05 m).
  bool rolling = false;
  double width_m = 3.0;
  double height_m = 3.0;
  double resolution_m = 0.05;
  // Rolling windows keep their corners on this lattice (the static map's origin), so the map's
  // cells copy one to one instead of being resampled.
  geometry::Point2D lattice_origin_m{};
  // costmap_2d's track_unknown_space: the cost of cells no layer wrote and of cells that enter a
  // rolling window is kUnknown. false: kFree (costmap_2d's default, what a local costmap uses).
  bool track_unknown_space = false;
};

// costmap_2d's LayeredCostmap: an ordered list of layers over one master grid (a PlanningGrid
// with costmap_2d's values, what the planners and trackers read). An update asks every layer, in
// order, which cells it changed (the inflation layer, last, grows them by its radius), resets those
// cells to the default cost and lets every layer write them in order: the static layer overwrites,
// the others combine by max. Only those cells are recomputed.
//
// In rolling mode update(robot pose) first moves the window by whole cells so the robot stays in
// the middle: master and layer grids are shifted, not recomputed, and only the cells that entered
// (and what the inflation of their obstacles reaches) are computed.
class LayeredCostmap {
 public:
  // Throws std::invalid_argument on a non-positive or non-finite size or resolution (rolling) or
  // a non-finite lattice origin.
  explicit LayeredCostmap(const LayeredCostmapOptions& options = {});

  const LayeredCostmapOptions& options() const { return options_; }
  bool rolling() const { return options_.rolling; }

  // Adds a layer above the others and returns it (the caller feeds it observations through the
  // reference, which stays valid). Throws std::logic_error when a layer of that name exists.
  template <class Layer>
  Layer& add(std::unique_ptr<Layer> layer) {
    Layer& out = *layer;
    add_layer(std::move(layer));
    return out;
  }
  CostmapLayer& add_layer(std::unique_ptr<CostmapLayer> layer);
  const std::vector<std::unique_ptr<CostmapLayer>>& layers() const { return layers_; }
  // The layer called `name`, or null.
  CostmapLayer* find(std::string_view name) const;

  // Global mode: the master grid takes this geometry (a static map's) and every cell is recomputed
  // at the next update. Throws std::invalid_argument on a bad geometry and std::logic_error in
  // rolling mode.
  void resize(int width_cells, int height_cells, double resolution_m, geometry::Pose2D origin);
  void resize_to(const mapping::OccupancyGrid& map);

  // Folds in what the layers received and recomputes the cells that changed; in rolling mode
  // recentres the window on the robot first (a non-finite pose then changes nothing). Returns the
  // cells recomputed (empty when nothing changed or the costmap has no geometry yet).
  CellBounds update(const geometry::Pose2D& robot_in_map);
  // Recomputes every cell at the next update (a global rebuild), and runs that update.
  CellBounds rebuild(const geometry::Pose2D& robot_in_map = {});

  const planning::PlanningGrid& master() const { return master_; }
  // A copy of the master for readers on other threads or later ticks (a tracker's local costmap).
  std::shared_ptr<const planning::PlanningGrid> snapshot() const;
  std::uint8_t default_cost() const;

 private:
  void move_window(const geometry::Pose2D& robot_in_map);
  geometry::Pose2D window_origin_for(const geometry::Pose2D& robot_in_map) const;
  void set_geometry(planning::PlanningGrid grid);

  LayeredCostmapOptions options_;
  int rolling_width_cells_ = 0;
  int rolling_height_cells_ = 0;
  std::vector<std::unique_ptr<CostmapLayer>> layers_;
  planning::PlanningGrid master_;
  CellBounds dirty_;  // recomputed at the next update whatever the layers say
};

}  // namespace mobot::costmap
