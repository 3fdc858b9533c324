#include "core/slam/submap.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace mobot::slam {

Submap::Submap(std::span<const SubmapScan> scans, const SubmapOptions& options,
               const std::optional<MapBox>& region) {
  if (!(options.resolution_m > 0.0) || !(options.sigma_m > 0.0) || !(options.max_gap_m >= 0.0) ||
      !(options.max_collinear_gap_m >= 0.0) || !(options.collinear_tolerance_m >= 0.0) ||
      !std::isfinite(options.resolution_m) || !std::isfinite(options.sigma_m)) {
    throw std::invalid_argument("SubmapOptions: resolution and sigma must be > 0");
  }
  // A point farther than the smear's reach outside the region cannot raise a cell inside it.
  const double reach_m = 3.0 * options.sigma_m + options.resolution_m;
  // Scans' points stay in beam order, one polyline per scan, so neighbouring returns can be joined.
  std::vector<geometry::Point2D> points;
  std::vector<std::size_t> scan_ends;
  for (const SubmapScan& scan : scans) {
    if (!geometry::is_finite(scan.base_in_map)) continue;
    for (const auto& p : scan.points_in_base) {
      const geometry::Point2D m = geometry::transform_point(scan.base_in_map, p);
      if (!std::isfinite(m.x) || !std::isfinite(m.y)) continue;
      if (region && (m.x < region->min_x_m - reach_m || m.x > region->max_x_m + reach_m ||
                     m.y < region->min_y_m - reach_m || m.y > region->max_y_m + reach_m)) {
        continue;
      }
      points.push_back(m);
    }
    scan_ends.push_back(points.size());
  }
  point_count_ = points.size();
  if (points.empty()) return;
  // The grid covers the points (plus the smear's reach), clipped to the region: cells beyond
  // either hold nothing or are never looked at.
  GridLimits limits = GridLimits::covering(points, options.resolution_m, reach_m);
  if (region) {
    const geometry::Point2D corners[] = {{region->min_x_m, region->min_y_m},
                                         {region->max_x_m, region->max_y_m}};
    const GridLimits box = GridLimits::covering(corners, options.resolution_m, 0.0);
    const double res = options.resolution_m;
    const double min_x = std::max(limits.origin_x_m, box.origin_x_m);
    const double min_y = std::max(limits.origin_y_m, box.origin_y_m);
    const double max_x =
        std::min(limits.origin_x_m + limits.width * res, box.origin_x_m + box.width * res);
    const double max_y =
        std::min(limits.origin_y_m + limits.height * res, box.origin_y_m + box.height * res);
    if (!(max_x > min_x) || !(max_y > min_y)) return;
    limits.origin_x_m = min_x;
    limits.origin_y_m = min_y;
    limits.width = static_cast<int>(std::lround((max_x - min_x) / res));
    limits.height = static_cast<int>(std::lround((max_y - min_y) / res));
    if (limits.width <= 0 || limits.height <= 0) return;
  }
  field_ = ProbabilityGrid(limits);
  std::size_t begin = 0;
  for (const std::size_t end : scan_ends) {
    field_.smear_polyline(std::span<const geometry::Point2D>(points).subspan(begin, end - begin),
                          options.sigma_m, options.max_gap_m, options.max_collinear_gap_m,
                          options.collinear_tolerance_m);
    begin = end;
  }
}

MapBox box_around(std::span<const geometry::Point2D> points_in_base, const geometry::Pose2D& pose,
                  double margin_m) {
  MapBox box{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
             -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  auto add = [&](const geometry::Point2D& m) {
    box.min_x_m = std::min(box.min_x_m, m.x);
    box.min_y_m = std::min(box.min_y_m, m.y);
    box.max_x_m = std::max(box.max_x_m, m.x);
    box.max_y_m = std::max(box.max_y_m, m.y);
  };
  add({pose.x, pose.y});
  for (const auto& p : points_in_base) add(geometry::transform_point(pose, p));
  box.min_x_m -= margin_m;
  box.min_y_m -= margin_m;
  box.max_x_m += margin_m;
  box.max_y_m += margin_m;
  return box;
}

}  // namespace mobot::slam
