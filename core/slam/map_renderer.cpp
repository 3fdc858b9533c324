#include "core/slam/map_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace mobot::slam {

namespace {

void check_options(const MapRenderOptions& options) {
  const bool finite = std::isfinite(options.resolution_m) && std::isfinite(options.align_m) &&
                      std::isfinite(options.margin_m) &&
                      std::isfinite(options.occupied_hit_ratio) &&
                      std::isfinite(options.max_range_m);
  if (!finite || options.resolution_m <= 0.0 || options.align_m < 0.0 || options.margin_m < 0.0 ||
      options.occupied_hit_ratio <= 0.0 || options.occupied_hit_ratio > 1.0 ||
      options.min_visits < 1 || options.max_range_m <= 0.0) {
    throw std::invalid_argument(
        "MapRenderOptions: resolution > 0, align and margin >= 0, 0 < hit ratio <= 1, "
        "min_visits >= 1, max_range > 0");
  }
}

struct Bounds {
  double min_x = std::numeric_limits<double>::infinity();
  double min_y = std::numeric_limits<double>::infinity();
  double max_x = -std::numeric_limits<double>::infinity();
  double max_y = -std::numeric_limits<double>::infinity();
  void add(const geometry::Point2D& p) {
    min_x = std::min(min_x, p.x);
    min_y = std::min(min_y, p.y);
    max_x = std::max(max_x, p.x);
    max_y = std::max(max_y, p.y);
  }
  bool empty() const { return !(min_x <= max_x); }
};

// Ends a ray at `max_range_m` from its start: misses carry the scan's usable range, but a renderer
// may be asked for less.
geometry::Point2D clip(const geometry::Point2D& from, const geometry::Point2D& to,
                       double max_range_m, bool& clipped) {
  const double dx = to.x - from.x;
  const double dy = to.y - from.y;
  const double length_m = std::hypot(dx, dy);
  clipped = length_m > max_range_m;
  if (!clipped) return to;
  const double k = max_range_m / length_m;
  return {from.x + k * dx, from.y + k * dy};
}

}  // namespace

mapping::OccupancyGrid render_occupancy_grid(std::span<const PosedScan> scans,
                                             const MapRenderOptions& options) {
  check_options(options);
  Bounds bounds;
  for (const PosedScan& scan : scans) {
    if (scan.points == nullptr || !geometry::is_finite(scan.base_in_map)) continue;
    const geometry::Point2D origin =
        geometry::transform_point(scan.base_in_map, scan.points->sensor_origin_in_base);
    bounds.add(origin);
    for (const auto& p : scan.points->points_in_base) {
      bool clipped = false;
      bounds.add(clip(origin, geometry::transform_point(scan.base_in_map, p), options.max_range_m,
                      clipped));
    }
    for (const auto& p : scan.points->misses_in_base) {
      bool clipped = false;
      bounds.add(clip(origin, geometry::transform_point(scan.base_in_map, p), options.max_range_m,
                      clipped));
    }
  }
  if (bounds.empty()) return {};

  const double res = options.resolution_m;
  double origin_x = bounds.min_x - options.margin_m;
  double origin_y = bounds.min_y - options.margin_m;
  if (options.align_m > 0.0) {
    origin_x = std::floor(origin_x / options.align_m) * options.align_m;
    origin_y = std::floor(origin_y / options.align_m) * options.align_m;
  }
  const int width = static_cast<int>(std::ceil((bounds.max_x + options.margin_m - origin_x) / res));
  const int height =
      static_cast<int>(std::ceil((bounds.max_y + options.margin_m - origin_y) / res));
  mapping::OccupancyGrid grid(std::max(width, 1), std::max(height, 1), res,
                              geometry::Pose2D{origin_x, origin_y, 0.0});

  std::vector<std::uint32_t> hits(static_cast<std::size_t>(grid.width()) * grid.height(), 0);
  std::vector<std::uint32_t> visits(hits.size(), 0);
  auto index = [&](mapping::CellIndex c) {
    return static_cast<std::size_t>(c.y) * static_cast<std::size_t>(grid.width()) +
           static_cast<std::size_t>(c.x);
  };

  // Bresenham from the sensor's cell to the end cell; every cell before the end is passed through.
  auto cast = [&](mapping::CellIndex from, mapping::CellIndex to, bool end_is_hit) {
    int x = from.x;
    int y = from.y;
    const int dx = std::abs(to.x - from.x);
    const int dy = -std::abs(to.y - from.y);
    const int sx = from.x < to.x ? 1 : -1;
    const int sy = from.y < to.y ? 1 : -1;
    int err = dx + dy;
    while (x != to.x || y != to.y) {
      const mapping::CellIndex cell{x, y};
      if (grid.contains(cell)) ++visits[index(cell)];
      const int e2 = 2 * err;
      if (e2 >= dy) {
        err += dy;
        x += sx;
      }
      if (e2 <= dx) {
        err += dx;
        y += sy;
      }
    }
    if (grid.contains(to)) {
      ++visits[index(to)];
      if (end_is_hit) ++hits[index(to)];
    }
  };

  for (const PosedScan& scan : scans) {
    if (scan.points == nullptr || !geometry::is_finite(scan.base_in_map)) continue;
    const geometry::Point2D origin =
        geometry::transform_point(scan.base_in_map, scan.points->sensor_origin_in_base);
    const mapping::CellIndex origin_cell = grid.cell_at_unchecked(origin);
    for (const auto& p : scan.points->points_in_base) {
      bool clipped = false;
      const geometry::Point2D end = clip(origin, geometry::transform_point(scan.base_in_map, p),
                                         options.max_range_m, clipped);
      cast(origin_cell, grid.cell_at_unchecked(end), !clipped);
    }
    for (const auto& p : scan.points->misses_in_base) {
      bool clipped = false;
      const geometry::Point2D end = clip(origin, geometry::transform_point(scan.base_in_map, p),
                                         options.max_range_m, clipped);
      cast(origin_cell, grid.cell_at_unchecked(end), false);
    }
  }

  auto& cells = grid.mutable_cells();
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (visits[i] < static_cast<std::uint32_t>(options.min_visits)) continue;
    const double ratio = static_cast<double>(hits[i]) / static_cast<double>(visits[i]);
    cells[i] = ratio >= options.occupied_hit_ratio ? mapping::OccupancyGrid::kOccupied
                                                   : mapping::OccupancyGrid::kFree;
  }
  return grid;
}

}  // namespace mobot::slam
