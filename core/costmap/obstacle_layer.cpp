#include "core/costmap/obstacle_layer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/costmap/cost_combination.h"
#include "core/costmap/grid_shift.h"
#include "core/costmap/ray_trace.h"
#include "core/numeric/finite.h"

namespace mobot::costmap {
namespace {

using planning::PlanningGrid;

}  // namespace

ObstacleLayer::ObstacleLayer(const ObstacleLayerOptions& options) : options_(options) {
  if (!finite_non_negative(options.obstacle_range_m) ||
      !finite_non_negative(options.raytrace_range_m)) {
    throw std::invalid_argument("obstacle layer ranges must be finite and non-negative");
  }
}

bool ObstacleLayer::add_scan(const msgs::LaserScan& scan, const geometry::Pose2D& sensor_in_map) {
  if (!geometry::is_finite(sensor_in_map) || !std::isfinite(scan.angle_min_rad) ||
      !std::isfinite(scan.angle_increment_rad) || !std::isfinite(scan.range_min_m) ||
      !std::isfinite(scan.range_max_m)) {
    return false;
  }
  Observation observation;
  observation.origin_in_map = {sensor_in_map.x, sensor_in_map.y};
  observation.clear_to_in_map.reserve(scan.ranges_m.size());
  const double range_max = scan.range_max_m;
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double range = scan.ranges_m[i];
    if (std::isnan(range) || range < scan.range_min_m) continue;
    const double angle = static_cast<double>(scan.angle_min_rad) +
                         static_cast<double>(i) * static_cast<double>(scan.angle_increment_rad);
    const double c = std::cos(angle);
    const double s = std::sin(angle);
    const auto at = [&](double r) {
      return geometry::transform_point(sensor_in_map, {r * c, r * s});
    };
    const bool returned = range < range_max;
    if (!returned && !options_.clear_on_no_return) continue;
    const double clear_range = std::min(returned ? range : range_max, options_.raytrace_range_m);
    observation.clear_to_in_map.push_back(at(clear_range));
    if (returned && range <= options_.obstacle_range_m)
      observation.hits_in_map.push_back(at(range));
  }
  pending_.push_back(std::move(observation));
  return true;
}

void ObstacleLayer::clear() {
  pending_.clear();
  if (!grid_.empty())
    std::fill(grid_.mutable_costs().begin(), grid_.mutable_costs().end(), PlanningGrid::kUnknown);
  cleared_ = true;
}

void ObstacleLayer::match_geometry(const PlanningGrid& master) {
  grid_ = PlanningGrid(master.width(), master.height(), master.resolution_m(), master.origin(),
                       PlanningGrid::kUnknown);
}

void ObstacleLayer::shift(const PlanningGrid& /*master*/, int dx_cells, int dy_cells) {
  shift_grid(grid_, dx_cells, dy_cells, PlanningGrid::kUnknown);
}

void ObstacleLayer::update_bounds(const PlanningGrid& master, CellBounds& bounds) {
  if (grid_.empty() || !same_geometry(grid_, master)) match_geometry(master);
  if (cleared_) {
    bounds.include(CellBounds::of_size(grid_.width(), grid_.height()));
    cleared_ = false;
  }
  // Clear every queued scan first, then mark: costmap_2d's order.
  for (const Observation& observation : pending_) {
    for (const geometry::Point2D& end : observation.clear_to_in_map) {
      const auto segment = clip_to_grid(grid_, observation.origin_in_map, end);
      if (!segment) continue;
      bounds.include(segment->from);
      bounds.include(segment->to);
      trace_cells(segment->from, segment->to,
                  [this](mapping::CellIndex cell) { grid_.set_cost(cell, PlanningGrid::kFree); });
    }
  }
  for (const Observation& observation : pending_) {
    for (const geometry::Point2D& hit : observation.hits_in_map) {
      if (const auto cell = grid_.cell_at(hit)) {
        grid_.set_cost(*cell, PlanningGrid::kLethal);
        bounds.include(*cell);
      }
    }
  }
  pending_.clear();
}

void ObstacleLayer::update(PlanningGrid& master, const CellBounds& bounds) {
  if (grid_.empty() || !same_geometry(grid_, master)) return;
  write_max(grid_, master, bounds);
}

}  // namespace mobot::costmap
