#pragma once

// Test helper: a synthetic floor plan and a ray-casting laser, for the slam tests.

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/msgs/laser_scan.h"

namespace mobot::slam::testing {

struct Segment {
  geometry::Point2D a, b;
};

// A 12 x 8 m room with a pillar, a cabinet and an inner wall stub: enough asymmetric structure that
// every pose in it has a unique scan.
inline std::vector<Segment> synthetic_room() {
  std::vector<Segment> walls = {
      {{0, 0}, {12, 0}},
      {{12, 0}, {12, 8}},
      {{12, 8}, {0, 8}},
      {{0, 8}, {0, 0}},
      // inner wall stub
      {{6, 0}, {6, 3}},
      // pillar 0.6 x 0.6
      {{3, 5}, {3.6, 5}},
      {{3.6, 5}, {3.6, 5.6}},
      {{3.6, 5.6}, {3, 5.6}},
      {{3, 5.6}, {3, 5}},
      // cabinet 1.5 x 0.5 against the top wall
      {{8, 8}, {8, 7.5}},
      {{8, 7.5}, {9.5, 7.5}},
      {{9.5, 7.5}, {9.5, 8}},
      // a diagonal shelf
      {{10, 2}, {11, 3.2}},
  };
  return walls;
}

// Range from `origin` along `angle` to the nearest wall, or +inf.
inline double cast_ray(const std::vector<Segment>& walls, geometry::Point2D origin, double angle) {
  const double dx = std::cos(angle), dy = std::sin(angle);
  double best = std::numeric_limits<double>::infinity();
  for (const Segment& w : walls) {
    const double ex = w.b.x - w.a.x, ey = w.b.y - w.a.y;
    const double denom = dx * ey - dy * ex;
    if (std::abs(denom) < 1e-12) continue;
    const double ox = w.a.x - origin.x, oy = w.a.y - origin.y;
    const double t = (ox * ey - oy * ex) / denom;
    const double u = (ox * dy - oy * dx) / denom;
    if (t > 1e-9 && u >= 0.0 && u <= 1.0) best = std::min(best, t);
  }
  return best;
}

// A scan of `beams` beams over `fov_rad` centred ahead, taken with the base at `base_in_map` and
// the sensor mounted at `sensor_in_base`. Rays beyond range_max read range_max (no return).
inline msgs::LaserScan cast_scan(const std::vector<Segment>& walls,
                                 const geometry::Pose2D& base_in_map, int beams = 361,
                                 double fov_rad = 2.0 * std::numbers::pi,
                                 const geometry::Pose2D& sensor_in_base = {},
                                 double range_max_m = 16.0) {
  msgs::LaserScan scan;
  const bool full_circle = fov_rad >= 2.0 * std::numbers::pi - 1e-9;
  scan.angle_increment_rad = static_cast<float>(fov_rad / (full_circle ? beams : beams - 1));
  scan.angle_min_rad = static_cast<float>(-fov_rad / 2.0);
  scan.range_min_m = 0.05F;
  scan.range_max_m = static_cast<float>(range_max_m);
  scan.sensor_in_base = sensor_in_base;
  const geometry::Pose2D sensor = geometry::compose(base_in_map, sensor_in_base);
  for (int i = 0; i < beams; ++i) {
    const double angle = sensor.theta + scan.angle_min_rad + i * scan.angle_increment_rad;
    const double r = cast_ray(walls, {sensor.x, sensor.y}, angle);
    scan.ranges_m.push_back(static_cast<float>(std::min(r, range_max_m)));
  }
  return scan;
}

}  // namespace mobot::slam::testing
