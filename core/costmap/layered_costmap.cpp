#include "core/costmap/layered_costmap.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/costmap/grid_shift.h"

namespace mobot::costmap {

using planning::PlanningGrid;

LayeredCostmap::LayeredCostmap(const LayeredCostmapOptions& options) : options_(options) {
  if (!std::isfinite(options.lattice_origin_m.x) || !std::isfinite(options.lattice_origin_m.y)) {
    throw std::invalid_argument("costmap lattice origin must be finite");
  }
  if (options.rolling) {
    if (!(options.resolution_m > 0.0) || !std::isfinite(options.resolution_m) ||
        !(options.width_m > 0.0) || !std::isfinite(options.width_m) || !(options.height_m > 0.0) ||
        !std::isfinite(options.height_m)) {
      throw std::invalid_argument("a rolling costmap needs a positive finite size and resolution");
    }
    rolling_width_cells_ =
        std::max(1, static_cast<int>(std::lround(options.width_m / options.resolution_m)));
    rolling_height_cells_ =
        std::max(1, static_cast<int>(std::lround(options.height_m / options.resolution_m)));
  }
}

CostmapLayer& LayeredCostmap::add_layer(std::unique_ptr<CostmapLayer> layer) {
  if (!layer) throw std::logic_error("a costmap layer must not be null");
  if (find(layer->name()) != nullptr) {
    throw std::logic_error("costmap layer '" + std::string(layer->name()) + "' is added twice");
  }
  if (!master_.empty()) {
    layer->match_geometry(master_);
    dirty_ = CellBounds::of_size(master_.width(), master_.height());
  }
  layers_.push_back(std::move(layer));
  return *layers_.back();
}

CostmapLayer* LayeredCostmap::find(std::string_view name) const {
  for (const auto& layer : layers_) {
    if (layer->name() == name) return layer.get();
  }
  return nullptr;
}

std::uint8_t LayeredCostmap::default_cost() const {
  return options_.track_unknown_space ? PlanningGrid::kUnknown : PlanningGrid::kFree;
}

void LayeredCostmap::set_geometry(PlanningGrid grid) {
  master_ = std::move(grid);
  for (const auto& layer : layers_) layer->match_geometry(master_);
  dirty_ = CellBounds::of_size(master_.width(), master_.height());
}

void LayeredCostmap::resize(int width_cells, int height_cells, double resolution_m,
                            geometry::Pose2D origin) {
  if (options_.rolling) throw std::logic_error("a rolling costmap sizes itself");
  if (!geometry::is_finite(origin)) throw std::invalid_argument("costmap origin must be finite");
  set_geometry(PlanningGrid(width_cells, height_cells, resolution_m, origin, default_cost()));
}

void LayeredCostmap::resize_to(const mapping::OccupancyGrid& map) {
  resize(map.width(), map.height(), map.resolution_m(), map.origin());
}

geometry::Pose2D LayeredCostmap::window_origin_for(const geometry::Pose2D& robot_in_map) const {
  const double res = options_.resolution_m;
  const geometry::Point2D lattice = options_.lattice_origin_m;
  const auto snap = [res](double value) { return std::floor(value / res + 0.5) * res; };
  return {lattice.x + snap(robot_in_map.x - 0.5 * rolling_width_cells_ * res - lattice.x),
          lattice.y + snap(robot_in_map.y - 0.5 * rolling_height_cells_ * res - lattice.y), 0.0};
}

void LayeredCostmap::move_window(const geometry::Pose2D& robot_in_map) {
  const geometry::Pose2D wanted = window_origin_for(robot_in_map);
  if (master_.empty()) {
    set_geometry(PlanningGrid(rolling_width_cells_, rolling_height_cells_, options_.resolution_m,
                              wanted, default_cost()));
    return;
  }
  const double res = options_.resolution_m;
  // Whole cells by construction (both corners are on the lattice); rounding removes the noise.
  const double dx_cells = std::round((wanted.x - master_.origin().x) / res);
  const double dy_cells = std::round((wanted.y - master_.origin().y) / res);
  if (dx_cells == 0.0 && dy_cells == 0.0) return;
  if (std::abs(dx_cells) >= master_.width() || std::abs(dy_cells) >= master_.height()) {
    // Nothing is shared: start the window afresh where the robot is (a relocalisation).
    set_geometry(
        PlanningGrid(rolling_width_cells_, rolling_height_cells_, res, wanted, default_cost()));
    return;
  }
  const int dx = static_cast<int>(dx_cells);
  const int dy = static_cast<int>(dy_cells);
  shift_grid(master_, dx, dy, default_cost());
  for (const auto& layer : layers_) layer->shift(master_, dx, dy);
  for (const CellBounds& entered : entered_cells(master_.width(), master_.height(), dx, dy)) {
    dirty_.include(entered);
  }
}

CellBounds LayeredCostmap::update(const geometry::Pose2D& robot_in_map) {
  if (options_.rolling) {
    if (!geometry::is_finite(robot_in_map)) return {};
    move_window(robot_in_map);
  }
  if (master_.empty()) return {};
  CellBounds bounds = dirty_;
  dirty_ = {};
  for (const auto& layer : layers_) layer->update_bounds(master_, bounds);
  bounds = bounds.clipped(master_.width(), master_.height());
  if (bounds.empty()) return {};
  const std::uint8_t fill = default_cost();
  std::vector<std::uint8_t>& costs = master_.mutable_costs();
  for (int y = bounds.min_y; y <= bounds.max_y; ++y) {
    const auto row =
        costs.begin() + static_cast<std::ptrdiff_t>(master_.index_of({bounds.min_x, y}));
    std::fill(row, row + bounds.width(), fill);
  }
  for (const auto& layer : layers_) layer->update(master_, bounds);
  return bounds;
}

CellBounds LayeredCostmap::rebuild(const geometry::Pose2D& robot_in_map) {
  if (!master_.empty()) dirty_ = CellBounds::of_size(master_.width(), master_.height());
  return update(robot_in_map);
}

std::shared_ptr<const PlanningGrid> LayeredCostmap::snapshot() const {
  return std::make_shared<const PlanningGrid>(master_);
}

}  // namespace mobot::costmap
