#pragma once

// Test-only geometry for the estimation tests: walls as segments, an exact ray-cast laser and the
// exact map lines of the walls. Header-only so each test file can pull in what it uses.

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/msgs/laser_scan.h"
#include "core/perception/line_segment.h"

namespace mobot::estimation_sim {

struct Wall {
  geometry::Point2D a;
  geometry::Point2D b;
};

// A closed rectangular room [x0, x1] x [y0, y1].
inline std::vector<Wall> rectangle_room(double x0, double y0, double x1, double y1) {
  return {{{x0, y0}, {x1, y0}}, {{x1, y0}, {x1, y1}}, {{x1, y1}, {x0, y1}}, {{x0, y1}, {x0, y0}}};
}

// Distance along the ray from `origin` in direction `angle_rad` to the nearest wall, or +inf.
inline double cast_ray(const std::vector<Wall>& walls, const geometry::Point2D& origin,
                       double angle_rad) {
  const double dx = std::cos(angle_rad);
  const double dy = std::sin(angle_rad);
  double best = std::numeric_limits<double>::infinity();
  for (const Wall& w : walls) {
    const double ex = w.b.x - w.a.x;
    const double ey = w.b.y - w.a.y;
    const double denom = dx * ey - dy * ex;
    if (std::abs(denom) < 1e-12) continue;
    const double ox = w.a.x - origin.x;
    const double oy = w.a.y - origin.y;
    const double t = (ox * ey - oy * ex) / denom;
    const double u = (ox * dy - oy * dx) / denom;
    if (t > 1e-9 && u >= 0.0 && u <= 1.0 && t < best) best = t;
  }
  return best;
}

struct ScanSpec {
  int beams = 361;
  double fov_rad = std::numbers::pi;  // centred on the sensor's x axis
  double range_min_m = 0.1;
  double range_max_m = 30.0;
  double range_sigma_m = 0.0;
};

// A scan taken by a sensor mounted at sensor_in_base on a base at `base_in_map`.
inline msgs::LaserScan simulate_scan(const std::vector<Wall>& walls,
                                     const geometry::Pose2D& base_in_map,
                                     const geometry::Pose2D& sensor_in_base, const ScanSpec& spec,
                                     std::mt19937* rng = nullptr) {
  msgs::LaserScan scan;
  scan.sensor_in_base = sensor_in_base;
  scan.range_min_m = static_cast<float>(spec.range_min_m);
  scan.range_max_m = static_cast<float>(spec.range_max_m);
  const bool full = spec.fov_rad >= 2.0 * std::numbers::pi - 1e-9;
  const double increment = spec.fov_rad / (full ? spec.beams : spec.beams - 1);
  scan.angle_min_rad = static_cast<float>(full ? -std::numbers::pi : -spec.fov_rad / 2.0);
  scan.angle_increment_rad = static_cast<float>(increment);
  const geometry::Pose2D sensor = geometry::compose(base_in_map, sensor_in_base);
  std::normal_distribution<double> noise(0.0, spec.range_sigma_m > 0.0 ? spec.range_sigma_m : 1.0);
  for (int i = 0; i < spec.beams; ++i) {
    const double bearing =
        static_cast<double>(scan.angle_min_rad) + i * static_cast<double>(scan.angle_increment_rad);
    double range = cast_ray(walls, {sensor.x, sensor.y}, sensor.theta + bearing);
    if (std::isfinite(range) && rng != nullptr && spec.range_sigma_m > 0.0) range += noise(*rng);
    scan.ranges_m.push_back(std::isfinite(range) && range < spec.range_max_m
                                ? static_cast<float>(range)
                                : std::numeric_limits<float>::infinity());
  }
  return scan;
}

// The exact line of a wall, endpoints included.
inline perception::LineSegment wall_line(const Wall& w) {
  perception::LineSegment line;
  const double ex = w.b.x - w.a.x;
  const double ey = w.b.y - w.a.y;
  line.alpha_rad = std::atan2(ex, -ey);  // a normal of the wall direction
  line.rho_m = w.a.x * std::cos(line.alpha_rad) + w.a.y * std::sin(line.alpha_rad);
  line.start = w.a;
  line.end = w.b;
  line.has_endpoints = true;
  return perception::normalized(line);
}

inline std::vector<perception::LineSegment> wall_lines(const std::vector<Wall>& walls) {
  std::vector<perception::LineSegment> lines;
  for (const Wall& w : walls) lines.push_back(wall_line(w));
  return lines;
}

}  // namespace mobot::estimation_sim
