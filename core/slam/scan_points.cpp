#include "core/slam/scan_points.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

namespace mobot::slam {

namespace {

void check_options(const ScanPointsOptions& options) {
  if (!std::isfinite(options.max_range_m) || !std::isfinite(options.min_range_m) ||
      !std::isfinite(options.voxel_size_m) || options.max_range_m <= 0.0 ||
      options.min_range_m < 0.0 || options.voxel_size_m < 0.0 ||
      options.min_range_m > options.max_range_m) {
    throw std::invalid_argument(
        "ScanPointsOptions: ranges must be finite, 0 <= min <= max, max > 0, voxel >= 0");
  }
}

}  // namespace

ScanPoints scan_to_points(const msgs::LaserScan& scan, const ScanPointsOptions& options) {
  check_options(options);
  ScanPoints out;
  const geometry::Pose2D& mount = scan.sensor_in_base;
  out.sensor_origin_in_base = {mount.x, mount.y};
  if (!geometry::is_finite(mount) || !std::isfinite(scan.angle_min_rad) ||
      !std::isfinite(scan.angle_increment_rad)) {
    return out;
  }
  out.points_in_base.reserve(scan.ranges_m.size());
  const double min_range_m = std::max<double>(options.min_range_m, scan.range_min_m);
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double range_m = scan.ranges_m[i];
    if (std::isnan(range_m) || range_m < min_range_m) continue;
    const double angle_rad =
        static_cast<double>(scan.angle_min_rad) + static_cast<double>(i) * scan.angle_increment_rad;
    const double c = std::cos(angle_rad);
    const double s = std::sin(angle_rad);
    // A return beyond the usable range, or none at all (at or past range_max, +inf), still says the
    // space up to the usable range is free.
    const bool returned = range_m <= options.max_range_m && range_m < scan.range_max_m;
    const double length_m = returned ? range_m : options.max_range_m;
    const geometry::Point2D in_base =
        geometry::transform_point(mount, {length_m * c, length_m * s});
    (returned ? out.points_in_base : out.misses_in_base).push_back(in_base);
  }
  if (options.voxel_size_m > 0.0) {
    out.points_in_base = voxel_filter(out.points_in_base, options.voxel_size_m);
  }
  return out;
}

std::vector<geometry::Point2D> voxel_filter(const std::vector<geometry::Point2D>& points,
                                            double voxel_size_m) {
  if (!(voxel_size_m > 0.0)) return points;
  struct Sum {
    double x = 0.0, y = 0.0;
    int count = 0;
    std::size_t first = 0;
  };
  std::map<std::pair<long long, long long>, Sum> voxels;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    const std::pair<long long, long long> key{
        static_cast<long long>(std::floor(p.x / voxel_size_m)),
        static_cast<long long>(std::floor(p.y / voxel_size_m))};
    auto [it, inserted] = voxels.try_emplace(key);
    if (inserted) it->second.first = i;
    it->second.x += p.x;
    it->second.y += p.y;
    ++it->second.count;
  }
  // Keep the scan's order (by each voxel's first point): the beams' order is what a reader expects.
  std::vector<std::pair<std::size_t, geometry::Point2D>> ordered;
  ordered.reserve(voxels.size());
  for (const auto& [key, sum] : voxels) {
    ordered.emplace_back(sum.first, geometry::Point2D{sum.x / sum.count, sum.y / sum.count});
  }
  std::sort(ordered.begin(), ordered.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<geometry::Point2D> out;
  out.reserve(ordered.size());
  for (const auto& [index, point] : ordered) out.push_back(point);
  return out;
}

}  // namespace mobot::slam
