#include "core/costmap/range_sensor_layer.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/costmap/cost_combination.h"
#include "core/costmap/grid_shift.h"
#include "core/costmap/ray_trace.h"
#include "core/numeric/finite.h"

namespace mobot::costmap {
namespace {

using planning::PlanningGrid;

// The cells (clipped to the grid) of the square around `centre` with half-side radius_m.
CellBounds square_around(const PlanningGrid& grid, geometry::Point2D centre, double radius_m) {
  const geometry::Point2D c = grid.to_grid_frame_cells(centre);
  const double r = radius_m / grid.resolution_m();
  // Compare in floating point before converting: a far cone must not overflow the int cast.
  const double lo_x = std::max(c.x - r, 0.0);
  const double lo_y = std::max(c.y - r, 0.0);
  const double hi_x = std::min(c.x + r, grid.width() - 1.0);
  const double hi_y = std::min(c.y + r, grid.height() - 1.0);
  if (lo_x > hi_x || lo_y > hi_y) return {};
  return {static_cast<int>(lo_x), static_cast<int>(lo_y), static_cast<int>(hi_x),
          static_cast<int>(hi_y)};
}

}  // namespace

RangeSensorLayer::RangeSensorLayer(const RangeSensorLayerOptions& options) : options_(options) {
  if (!std::isfinite(options.max_mark_range_m) || !finite_non_negative(options.arc_thickness_m)) {
    throw std::invalid_argument("range sensor layer options must be finite and non-negative");
  }
}

bool RangeSensorLayer::add_readings(std::span<const msgs::RangeReading> readings,
                                    const geometry::Pose2D& base_in_map) {
  if (!geometry::is_finite(base_in_map)) return false;
  for (const msgs::RangeReading& reading : readings) {
    const double range = reading.range_m;
    if (!std::isfinite(range) || !geometry::is_finite(reading.sensor_in_base) ||
        !std::isfinite(reading.range_max_m) || !(reading.range_max_m > 0.0) ||
        !std::isfinite(reading.range_min_m) || range < reading.range_min_m ||
        !(reading.cone_rad > 0.0 && reading.cone_rad < std::numbers::pi)) {
      continue;
    }
    Cone cone;
    cone.sensor_in_map = geometry::compose(base_in_map, reading.sensor_in_base);
    cone.half_angle_rad = 0.5 * reading.cone_rad;
    // A tiny tolerance: a driver that reports "nothing" as range_max in float must count.
    const bool at_max = range >= reading.range_max_m * (1.0 - 1e-6);
    const bool trusted = options_.max_mark_range_m <= 0.0 || range <= options_.max_mark_range_m;
    if (at_max) {
      if (!options_.clear_on_max_reading) continue;
      cone.clear_to_m = reading.range_max_m;
    } else {
      cone.clear_to_m = range;  // less the arc's half thickness, applied with the grid known
      cone.echo = true;
      if (trusted) cone.mark_at_m = range;
    }
    pending_.push_back(cone);
  }
  return true;
}

void RangeSensorLayer::clear() {
  pending_.clear();
  if (!grid_.empty())
    std::fill(grid_.mutable_costs().begin(), grid_.mutable_costs().end(), PlanningGrid::kUnknown);
  cleared_ = true;
}

void RangeSensorLayer::match_geometry(const PlanningGrid& master) {
  grid_ = PlanningGrid(master.width(), master.height(), master.resolution_m(), master.origin(),
                       PlanningGrid::kUnknown);
}

void RangeSensorLayer::shift(const PlanningGrid& /*master*/, int dx_cells, int dy_cells) {
  shift_grid(grid_, dx_cells, dy_cells, PlanningGrid::kUnknown);
}

void RangeSensorLayer::clear_cone(const Cone& cone, CellBounds& bounds) {
  const double res = grid_.resolution_m();
  const double half_thickness = options_.arc_thickness_m > 0.0 ? 0.5 * options_.arc_thickness_m
                                                               : res * std::numbers::sqrt2 / 2;
  const double clear_to = cone.echo ? cone.clear_to_m - half_thickness : cone.clear_to_m;
  if (clear_to <= 0.0) return;
  const geometry::Point2D origin{cone.sensor_in_map.x, cone.sensor_in_map.y};
  const double ux = std::cos(cone.sensor_in_map.theta);
  const double uy = std::sin(cone.sensor_in_map.theta);
  const double cos_half = std::cos(cone.half_angle_rad);
  const CellBounds box = square_around(grid_, origin, clear_to);
  for (int y = box.min_y; y <= box.max_y; ++y) {
    for (int x = box.min_x; x <= box.max_x; ++x) {
      const geometry::Point2D centre = grid_.cell_center({x, y});
      const double vx = centre.x - origin.x;
      const double vy = centre.y - origin.y;
      const double d = std::hypot(vx, vy);
      if (d >= clear_to) continue;
      if (d > 0.5 * res && vx * ux + vy * uy < d * cos_half) continue;
      grid_.set_cost({x, y}, PlanningGrid::kFree);
      bounds.include(mapping::CellIndex{x, y});
    }
  }
  // The axis, for cones too narrow to hold a cell centre. It stops a cell short of the echo.
  const double axis_to = cone.echo ? std::max(0.0, clear_to - 0.5 * res) : clear_to;
  const auto segment =
      clip_to_grid(grid_, origin, {origin.x + axis_to * ux, origin.y + axis_to * uy});
  if (!segment) return;
  bounds.include(segment->from);
  bounds.include(segment->to);
  trace_cells(segment->from, segment->to,
              [this](mapping::CellIndex cell) { grid_.set_cost(cell, PlanningGrid::kFree); });
}

void RangeSensorLayer::mark_cone(const Cone& cone, CellBounds& bounds) {
  if (cone.mark_at_m < 0.0) return;
  const double res = grid_.resolution_m();
  const double half_thickness = options_.arc_thickness_m > 0.0 ? 0.5 * options_.arc_thickness_m
                                                               : res * std::numbers::sqrt2 / 2;
  const geometry::Point2D origin{cone.sensor_in_map.x, cone.sensor_in_map.y};
  const double ux = std::cos(cone.sensor_in_map.theta);
  const double uy = std::sin(cone.sensor_in_map.theta);
  const double cos_half = std::cos(cone.half_angle_rad);
  const double r = cone.mark_at_m;
  const CellBounds box = square_around(grid_, origin, r + half_thickness);
  for (int y = box.min_y; y <= box.max_y; ++y) {
    for (int x = box.min_x; x <= box.max_x; ++x) {
      const geometry::Point2D centre = grid_.cell_center({x, y});
      const double vx = centre.x - origin.x;
      const double vy = centre.y - origin.y;
      const double d = std::hypot(vx, vy);
      if (std::abs(d - r) > half_thickness || vx * ux + vy * uy < d * cos_half) continue;
      grid_.set_cost({x, y}, PlanningGrid::kLethal);
      bounds.include(mapping::CellIndex{x, y});
    }
  }
  if (const auto cell = grid_.cell_at({origin.x + r * ux, origin.y + r * uy})) {
    grid_.set_cost(*cell, PlanningGrid::kLethal);
    bounds.include(*cell);
  }
}

void RangeSensorLayer::update_bounds(const PlanningGrid& master, CellBounds& bounds) {
  if (grid_.empty() || !same_geometry(grid_, master)) match_geometry(master);
  if (cleared_) {
    bounds.include(CellBounds::of_size(grid_.width(), grid_.height()));
    cleared_ = false;
  }
  for (const Cone& cone : pending_) clear_cone(cone, bounds);
  for (const Cone& cone : pending_) mark_cone(cone, bounds);
  pending_.clear();
}

void RangeSensorLayer::update(PlanningGrid& master, const CellBounds& bounds) {
  if (grid_.empty() || !same_geometry(grid_, master)) return;
  write_max(grid_, master, bounds);
}

}  // namespace mobot::costmap
