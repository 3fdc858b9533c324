#include "core/perception/unmapped_obstacles.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/geometry/polyline.h"

namespace mobot::perception {

UnmappedObstacles::UnmappedObstacles(UnmappedObstaclesOptions options) : options_(options) {}

bool UnmappedObstacles::explained_by_map(const geometry::Point2D& point_in_map) const {
  if (!map_) return true;
  const auto cell = map_->cell_at(point_in_map);
  if (!cell) return true;  // beyond the map: nothing to plan around
  const int reach = options_.map_match_cells;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const mapping::CellIndex near{cell->x + dx, cell->y + dy};
      if (map_->contains(near) && map_->cost(near) >= planning::PlanningGrid::kLethal) return true;
    }
  }
  return false;
}

void UnmappedObstacles::observe_scan(const msgs::LaserScan& scan,
                                     const geometry::Pose2D& sensor_in_map) {
  scan_points_.clear();
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const float range_m = scan.ranges_m[i];
    if (!(range_m >= scan.range_min_m && range_m <= scan.range_max_m)) continue;
    const double angle_rad = scan.angle_min_rad + static_cast<double>(i) * scan.angle_increment_rad;
    const geometry::Point2D point = geometry::transform_point(
        sensor_in_map, {range_m * std::cos(angle_rad), range_m * std::sin(angle_rad)});
    if (!explained_by_map(point)) scan_points_.push_back(point);
  }
  merge_points();
}

void UnmappedObstacles::observe_ranges(std::span<const msgs::RangeReading> ring,
                                       const geometry::Pose2D& base_in_map, double now_s) {
  std::erase_if(range_echoes_, [&](const HeldEcho& echo) {
    return !(now_s - echo.seen_s <= options_.range_echo_hold_s);
  });
  if (echo_runs_.size() != ring.size()) echo_runs_.assign(ring.size(), EchoRun{});
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const msgs::RangeReading& reading = ring[i];
    EchoRun& run = echo_runs_[i];
    // range_max (or beyond): nothing echoed; NaN: not a reading.
    if (!(reading.range_m >= reading.range_min_m && reading.range_m < reading.range_max_m)) {
      run = {};
      continue;
    }
    const bool agrees = run.count > 0 &&
                        std::abs(reading.range_m - run.range_m) <= options_.range_echo_agreement_m;
    const int in_a_row = agrees ? std::min(run.count + 1, options_.range_echo_confirmations) : 1;
    run = {reading.range_m, in_a_row};
    if (run.count < options_.range_echo_confirmations) continue;
    const geometry::Pose2D sensor = geometry::compose(base_in_map, reading.sensor_in_base);
    const geometry::Point2D point = geometry::transform_point(sensor, {reading.range_m, 0.0});
    if (!explained_by_map(point)) range_echoes_.push_back({point, now_s});
  }
  merge_points();
}

void UnmappedObstacles::merge_points() {
  points_ = scan_points_;
  for (const auto& echo : range_echoes_) points_.push_back(echo.point);
}

bool UnmappedObstacles::blocks(const std::vector<geometry::Point2D>& path, double within_m) const {
  for (const auto& point : points_) {
    if (geometry::distance_to_polyline(path, point) < within_m) return true;
  }
  return false;
}

bool UnmappedObstacles::echo_is_wall(const msgs::RangeReading& reading,
                                     const geometry::Pose2D& sensor) const {
  const int samples = options_.cone_samples;
  for (int k = 0; k < samples; ++k) {
    const double angle_rad =
        reading.cone_rad * (samples > 1 ? static_cast<double>(k) / (samples - 1) - 0.5 : 0.0);
    if (explained_by_map(geometry::transform_point(
            sensor,
            {reading.range_m * std::cos(angle_rad), reading.range_m * std::sin(angle_rad)}))) {
      return true;
    }
  }
  return false;
}

std::vector<msgs::RangeReading> UnmappedObstacles::echoes_on_path(
    const msgs::SonarRing& ring, const geometry::Pose2D& base_in_map,
    const std::vector<geometry::Point2D>& path, double within_m) const {
  std::vector<msgs::RangeReading> echoes;
  echoes.reserve(ring.readings.size());
  for (const auto& reading : ring.readings) {
    msgs::RangeReading echo = reading;
    if (reading.range_m < reading.range_max_m) {
      const geometry::Pose2D sensor = geometry::compose(base_in_map, reading.sensor_in_base);
      const geometry::Point2D axis_point =
          geometry::transform_point(sensor, {reading.range_m, 0.0});
      // A wall on the map, or something the path already keeps clear of, is the planner's
      // business; the potential field is for what stands on the path and the map does not show.
      if (echo_is_wall(reading, sensor) ||
          !(geometry::distance_to_polyline(path, axis_point) < within_m)) {
        echo.range_m = reading.range_max_m;
      }
    }
    echoes.push_back(echo);
  }
  return echoes;
}

}  // namespace mobot::perception
