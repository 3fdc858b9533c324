#include "core/costmap/obstacle_grid_layer.h"

#include <algorithm>
#include <cmath>

#include "core/costmap/cost_combination.h"
#include "core/costmap/grid_shift.h"

namespace mobot::costmap {
namespace {

using planning::PlanningGrid;

// A rigid transform with its sine and cosine computed once (transform_point recomputes them).
struct Rigid {
  double c = 1.0;
  double s = 0.0;
  double tx = 0.0;
  double ty = 0.0;

  explicit Rigid(const geometry::Pose2D& pose)
      : c(std::cos(pose.theta)), s(std::sin(pose.theta)), tx(pose.x), ty(pose.y) {}
  geometry::Point2D operator()(double x, double y) const {
    return {tx + c * x - s * y, ty + s * x + c * y};
  }
};

}  // namespace

ObstacleGridLayer::ObstacleGridLayer(const ObstacleGridLayerOptions& options) : options_(options) {}

void ObstacleGridLayer::set_grids(std::vector<mapping::OccupancyGrid> grids) {
  sources_ = std::move(grids);
  changed_ = true;
}

void ObstacleGridLayer::rasterise(const mapping::OccupancyGrid& source,
                                  std::uint8_t occupied_threshold, PlanningGrid& target,
                                  const CellBounds& bounds) {
  const CellBounds b = bounds.clipped(target.width(), target.height());
  if (b.empty() || source.width() <= 0 || source.height() <= 0 || source.cells().empty()) return;
  const double res = target.resolution_m();
  const double source_res = source.resolution_m();
  // map -> target cells and map -> source cells, and source cells -> map.
  const Rigid target_from_map(geometry::inverse(target.origin()));
  const Rigid source_from_map(geometry::inverse(source.origin()));
  const Rigid map_from_source(source.origin());
  const Rigid map_from_target(target.origin());

  // The source cells that can reach the bounds: the bounds' corners in source cells, plus one.
  double lo_x = source.width();
  double lo_y = source.height();
  double hi_x = -1.0;
  double hi_y = -1.0;
  for (const auto& [cx, cy] : {std::pair{b.min_x, b.min_y},
                               {b.max_x + 1, b.min_y},
                               {b.min_x, b.max_y + 1},
                               {b.max_x + 1, b.max_y + 1}}) {
    const geometry::Point2D in_map = map_from_target(cx * res, cy * res);
    const geometry::Point2D in_source = source_from_map(in_map.x, in_map.y);
    lo_x = std::min(lo_x, in_source.x / source_res);
    lo_y = std::min(lo_y, in_source.y / source_res);
    hi_x = std::max(hi_x, in_source.x / source_res);
    hi_y = std::max(hi_y, in_source.y / source_res);
  }
  const int sx0 = static_cast<int>(std::max(0.0, std::floor(lo_x) - 1.0));
  const int sy0 = static_cast<int>(std::max(0.0, std::floor(lo_y) - 1.0));
  const int sx1 = static_cast<int>(std::min(source.width() - 1.0, std::floor(hi_x) + 1.0));
  const int sy1 = static_cast<int>(std::min(source.height() - 1.0, std::floor(hi_y) + 1.0));

  const auto mark = [&](int x, int y) {
    if (b.contains({x, y})) target.set_cost({x, y}, PlanningGrid::kLethal);
  };
  const auto to_target_cells = [&](double sx_m, double sy_m) {
    const geometry::Point2D in_map = map_from_source(sx_m, sy_m);
    const geometry::Point2D in_target = target_from_map(in_map.x, in_map.y);
    return geometry::Point2D{in_target.x / res, in_target.y / res};
  };
  const std::vector<std::uint8_t>& cells = source.cells();
  for (int sy = sy0; sy <= sy1; ++sy) {
    for (int sx = sx0; sx <= sx1; ++sx) {
      const std::uint8_t value =
          cells[static_cast<std::size_t>(sy) * static_cast<std::size_t>(source.width()) +
                static_cast<std::size_t>(sx)];
      if (value == mapping::OccupancyGrid::kUnknown || value < occupied_threshold) continue;
      const geometry::Point2D centre =
          to_target_cells((sx + 0.5) * source_res, (sy + 0.5) * source_res);
      mark(static_cast<int>(std::floor(centre.x)), static_cast<int>(std::floor(centre.y)));
      // The target cells whose centres this source cell covers: search the box of its corners.
      double min_x = b.max_x + 1.0;
      double min_y = b.max_y + 1.0;
      double max_x = b.min_x - 1.0;
      double max_y = b.min_y - 1.0;
      for (const auto& [cx, cy] : {std::pair{0, 0}, {1, 0}, {0, 1}, {1, 1}}) {
        const geometry::Point2D corner =
            to_target_cells((sx + cx) * source_res, (sy + cy) * source_res);
        min_x = std::min(min_x, corner.x);
        min_y = std::min(min_y, corner.y);
        max_x = std::max(max_x, corner.x);
        max_y = std::max(max_y, corner.y);
      }
      const int x0 =
          std::max(b.min_x, static_cast<int>(std::floor(std::max(min_x, b.min_x - 1.0))));
      const int y0 =
          std::max(b.min_y, static_cast<int>(std::floor(std::max(min_y, b.min_y - 1.0))));
      const int x1 =
          std::min(b.max_x, static_cast<int>(std::floor(std::min(max_x, b.max_x + 1.0))));
      const int y1 =
          std::min(b.max_y, static_cast<int>(std::floor(std::min(max_y, b.max_y + 1.0))));
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          const geometry::Point2D in_map = map_from_target((x + 0.5) * res, (y + 0.5) * res);
          const geometry::Point2D in_source = source_from_map(in_map.x, in_map.y);
          if (static_cast<int>(std::floor(in_source.x / source_res)) == sx &&
              static_cast<int>(std::floor(in_source.y / source_res)) == sy) {
            target.set_cost({x, y}, PlanningGrid::kLethal);
          }
        }
      }
    }
  }
}

void ObstacleGridLayer::rasterise_all(const CellBounds& bounds) {
  for (const mapping::OccupancyGrid& source : sources_) {
    rasterise(source, options_.occupied_threshold, grid_, bounds);
  }
}

void ObstacleGridLayer::match_geometry(const PlanningGrid& master) {
  grid_ = PlanningGrid(master.width(), master.height(), master.resolution_m(), master.origin(),
                       PlanningGrid::kUnknown);
  rasterise_all(CellBounds::of_size(grid_.width(), grid_.height()));
  changed_ = true;
}

void ObstacleGridLayer::shift(const PlanningGrid& /*master*/, int dx_cells, int dy_cells) {
  shift_grid(grid_, dx_cells, dy_cells, PlanningGrid::kUnknown);
  for (const CellBounds& entered :
       entered_cells(grid_.width(), grid_.height(), dx_cells, dy_cells)) {
    rasterise_all(entered);
  }
}

void ObstacleGridLayer::update_bounds(const PlanningGrid& master, CellBounds& bounds) {
  if (grid_.empty() || !same_geometry(grid_, master)) {
    match_geometry(master);
  } else if (changed_) {
    std::fill(grid_.mutable_costs().begin(), grid_.mutable_costs().end(), PlanningGrid::kUnknown);
    rasterise_all(CellBounds::of_size(grid_.width(), grid_.height()));
  }
  if (!changed_) return;
  bounds.include(CellBounds::of_size(master.width(), master.height()));
  changed_ = false;
}

void ObstacleGridLayer::update(PlanningGrid& master, const CellBounds& bounds) {
  if (grid_.empty() || !same_geometry(grid_, master)) return;
  write_max(grid_, master, bounds);
}

}  // namespace mobot::costmap
