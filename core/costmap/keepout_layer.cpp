#include "core/costmap/keepout_layer.h"

#include <algorithm>
#include <cmath>

#include "core/costmap/cost_combination.h"
#include "core/costmap/grid_shift.h"
#include "core/costmap/ray_trace.h"

namespace mobot::costmap {

using planning::PlanningGrid;

KeepoutLayer::KeepoutLayer(const KeepoutLayerOptions& options) : options_(options) {}

std::optional<std::string> KeepoutLayer::set_zones(
    const std::vector<std::vector<geometry::Point2D>>& zones) {
  if (zones.size() > options_.max_zones) {
    return "at most " + std::to_string(options_.max_zones) + " keep-out zones, got " +
           std::to_string(zones.size());
  }
  std::vector<geometry::SimplePolygon> polygons;
  polygons.reserve(zones.size());
  for (std::size_t i = 0; i < zones.size(); ++i) {
    if (const auto why = geometry::SimplePolygon::error(zones[i])) {
      return "zone " + std::to_string(i) + ": " + *why;
    }
    polygons.emplace_back(zones[i]);
  }
  zones_ = std::move(polygons);
  changed_ = true;
  return std::nullopt;
}

void KeepoutLayer::rasterise(const CellBounds& bounds) {
  const CellBounds b = bounds.clipped(grid_.width(), grid_.height());
  if (b.empty()) return;
  for (const geometry::SimplePolygon& zone : zones_) {
    // The zone's box in grid cells (through every vertex: the grid may be rotated).
    double lo_x = b.max_x + 1.0;
    double lo_y = b.max_y + 1.0;
    double hi_x = b.min_x - 1.0;
    double hi_y = b.min_y - 1.0;
    for (const geometry::Point2D& vertex : zone.vertices()) {
      const geometry::Point2D c = grid_.to_grid_frame_cells(vertex);
      lo_x = std::min(lo_x, c.x);
      lo_y = std::min(lo_y, c.y);
      hi_x = std::max(hi_x, c.x);
      hi_y = std::max(hi_y, c.y);
    }
    const CellBounds box = CellBounds{static_cast<int>(std::floor(std::max(lo_x, b.min_x - 1.0))),
                                      static_cast<int>(std::floor(std::max(lo_y, b.min_y - 1.0))),
                                      static_cast<int>(std::floor(std::min(hi_x, b.max_x + 1.0))),
                                      static_cast<int>(std::floor(std::min(hi_y, b.max_y + 1.0)))}
                               .intersected(b);
    for (int y = box.min_y; y <= box.max_y; ++y) {
      for (int x = box.min_x; x <= box.max_x; ++x) {
        if (zone.contains(grid_.cell_center({x, y}))) grid_.set_cost({x, y}, PlanningGrid::kLethal);
      }
    }
    const std::vector<geometry::Point2D>& v = zone.vertices();
    for (std::size_t i = 0; i < v.size(); ++i) {
      const auto segment = clip_to_grid(grid_, v[i], v[(i + 1) % v.size()]);
      if (!segment) continue;
      trace_cells(segment->from, segment->to, [this, &b](mapping::CellIndex cell) {
        if (b.contains(cell)) grid_.set_cost(cell, PlanningGrid::kLethal);
      });
    }
  }
}

void KeepoutLayer::match_geometry(const PlanningGrid& master) {
  grid_ = PlanningGrid(master.width(), master.height(), master.resolution_m(), master.origin(),
                       PlanningGrid::kUnknown);
  rasterise(CellBounds::of_size(grid_.width(), grid_.height()));
  changed_ = true;
}

void KeepoutLayer::shift(const PlanningGrid& /*master*/, int dx_cells, int dy_cells) {
  shift_grid(grid_, dx_cells, dy_cells, PlanningGrid::kUnknown);
  for (const CellBounds& entered :
       entered_cells(grid_.width(), grid_.height(), dx_cells, dy_cells)) {
    rasterise(entered);
  }
}

void KeepoutLayer::update_bounds(const PlanningGrid& master, CellBounds& bounds) {
  if (grid_.empty() || !same_geometry(grid_, master)) {
    match_geometry(master);
  } else if (changed_) {
    std::fill(grid_.mutable_costs().begin(), grid_.mutable_costs().end(), PlanningGrid::kUnknown);
    rasterise(CellBounds::of_size(grid_.width(), grid_.height()));
  }
  if (!changed_) return;
  bounds.include(CellBounds::of_size(master.width(), master.height()));
  changed_ = false;
}

void KeepoutLayer::update(PlanningGrid& master, const CellBounds& bounds) {
  if (grid_.empty() || !same_geometry(grid_, master)) return;
  write_max(grid_, master, bounds);
}

}  // namespace mobot::costmap
