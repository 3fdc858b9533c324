#include "core/slam/submap.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace mobot::slam {

Submap::Submap(std::span<const SubmapScan> scans, const SubmapOptions& options,
               const std::optional<MapBox>& region) {
  if (!(options.resolution_m > 0.0) || !(options.sigma_m > 0.0) ||
      !std::isfinite(options.resolution_m) || !std::isfinite(options.sigma_m)) {
    throw std::invalid_argument("SubmapOptions: resolution and sigma must be > 0");
  }
  // A point farther than the smear's reach outside the region cannot raise a cell inside it.
  const double reach_m = 3.0 * options.sigma_m + options.resolution_m;
  std::vector<geometry::Point2D> points;
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
  }
  point_count_ = points.size();
  if (points.empty()) return;
  GridLimits limits;
  if (region) {
    const geometry::Point2D corners[] = {{region->min_x_m, region->min_y_m},
                                         {region->max_x_m, region->max_y_m}};
    limits = GridLimits::covering(corners, options.resolution_m, 0.0);
  } else {
    limits = GridLimits::covering(points, options.resolution_m, reach_m);
  }
  field_ = ProbabilityGrid(limits);
  field_.smear_points(points, options.sigma_m);
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
