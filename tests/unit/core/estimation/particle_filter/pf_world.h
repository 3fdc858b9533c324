#pragma once

// Test-only world for the particle-filter tests: a non-symmetric room as wall segments (ray-cast
// scans) and as an occupancy grid (the filter's map), a loop through it, and odometry with noise.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "core/msgs/laser_scan.h"
#include "tests/unit/core/estimation/synthetic_world.h"

namespace mobot::pf_world {

using estimation_sim::Wall;

struct Box {
  double x0, y0, x1, y1;
  bool contains(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
};

// A 10 x 8 m room with a wall stub and two boxes placed so that no rotation or mirror of the
// room maps it onto itself.
struct Room {
  std::vector<Wall> walls;
  std::vector<Box> boxes;
  double width_m = 10.0;
  double height_m = 8.0;
  bool has_stub = true;

  bool free(double x, double y) const {
    if (x <= 0.0 || y <= 0.0 || x >= width_m || y >= height_m) return false;
    if (has_stub && std::abs(x - 6.0) < 0.05 && y <= 3.0) return false;
    return std::none_of(boxes.begin(), boxes.end(), [&](const Box& b) { return b.contains(x, y); });
  }
};

inline Room asymmetric_room() {
  Room room;
  room.walls = estimation_sim::rectangle_room(0.0, 0.0, room.width_m, room.height_m);
  room.walls.push_back({{6.0, 0.0}, {6.0, 3.0}});
  room.boxes = {{2.0, 5.0, 3.0, 6.0}, {7.0, 6.0, 8.0, 7.0}};
  for (const Box& b : room.boxes) {
    const auto box_walls = estimation_sim::rectangle_room(b.x0, b.y0, b.x1, b.y1);
    room.walls.insert(room.walls.end(), box_walls.begin(), box_walls.end());
  }
  return room;
}

// The same room without the stub and with its boxes placed so that turning it half round about
// its centre maps it onto itself: every pose has a twin that sees the same scan.
inline Room half_turn_symmetric_room() {
  Room room;
  room.has_stub = false;
  room.walls = estimation_sim::rectangle_room(0.0, 0.0, room.width_m, room.height_m);
  room.boxes = {{2.0, 5.0, 3.0, 6.0}, {7.0, 2.0, 8.0, 3.0}};
  for (const Box& b : room.boxes) {
    const auto box_walls = estimation_sim::rectangle_room(b.x0, b.y0, b.x1, b.y1);
    room.walls.insert(room.walls.end(), box_walls.begin(), box_walls.end());
  }
  return room;
}

// The room rasterised at `resolution_m` with a margin of unknown cells around it: walls occupied,
// the inside free, the outside unknown. The cells are centred on multiples of the resolution, so
// the walls (all on such multiples) run through the centres of their cells: a grid aligned with
// the walls' edges would shift the mapped room by half a cell.
inline mapping::OccupancyGrid room_grid(const Room& room, double resolution_m = 0.05) {
  const double margin = 0.5;
  const int width = static_cast<int>(std::lround((room.width_m + 2 * margin) / resolution_m));
  const int height = static_cast<int>(std::lround((room.height_m + 2 * margin) / resolution_m));
  const double corner = -margin - resolution_m / 2.0;
  mapping::OccupancyGrid grid(width, height, resolution_m, {corner, corner, 0.0},
                              mapping::OccupancyGrid::kUnknown);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const geometry::Point2D c = grid.cell_center({x, y});
      if (room.free(c.x, c.y)) grid.set({x, y}, mapping::OccupancyGrid::kFree);
    }
  }
  for (const Wall& w : room.walls) {
    const double length = std::hypot(w.b.x - w.a.x, w.b.y - w.a.y);
    const int steps = static_cast<int>(std::ceil(length / (resolution_m / 4.0)));
    for (int i = 0; i <= steps; ++i) {
      const double t = static_cast<double>(i) / steps;
      const auto cell = grid.cell_at({w.a.x + t * (w.b.x - w.a.x), w.a.y + t * (w.b.y - w.a.y)});
      if (cell) grid.set(*cell, mapping::OccupancyGrid::kOccupied);
    }
  }
  return grid;
}

// A loop through the room at 2 cm per tick (1 m/s at 50 Hz), turning on the spot at corners.
inline std::vector<geometry::Pose2D> loop_path(int laps = 3) {
  const std::vector<geometry::Point2D> corners = {{1.2, 1.5}, {4.8, 1.5}, {4.8, 4.0},
                                                  {9.0, 4.0}, {9.0, 7.2}, {1.2, 7.2}};
  constexpr double kStep_m = 0.02;
  constexpr double kTurn_rad = 0.04;
  std::vector<geometry::Pose2D> path;
  double heading = 0.0;
  for (int lap = 0; lap < laps; ++lap) {
    for (std::size_t i = 0; i < corners.size(); ++i) {
      const geometry::Point2D a = corners[i];
      const geometry::Point2D b = corners[(i + 1) % corners.size()];
      const double target = std::atan2(b.y - a.y, b.x - a.x);
      while (std::abs(geometry::wrap_angle(target - heading)) > 1e-9) {
        const double turn =
            std::clamp(geometry::wrap_angle(target - heading), -kTurn_rad, kTurn_rad);
        heading = geometry::wrap_angle(heading + turn);
        path.push_back({a.x, a.y, heading});
      }
      const double length = std::hypot(b.x - a.x, b.y - a.y);
      const int steps = static_cast<int>(std::ceil(length / kStep_m));
      for (int k = 1; k <= steps; ++k) {
        const double t = static_cast<double>(k) / steps;
        path.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), heading});
      }
    }
  }
  return path;
}

// Wheel odometry's view of a step: the true body-frame increment with a few per cent of noise.
class NoisyOdometry {
 public:
  explicit NoisyOdometry(std::uint64_t seed, double noise = 0.03) : rng_(seed), noise_(noise) {}

  geometry::Pose2D step(const geometry::Pose2D& odom, const geometry::Pose2D& truth_before,
                        const geometry::Pose2D& truth_after) {
    geometry::Pose2D delta = geometry::compose(geometry::inverse(truth_before), truth_after);
    std::normal_distribution<double> unit(0.0, 1.0);
    delta.x *= 1.0 + noise_ * unit(rng_);
    delta.theta = delta.theta * (1.0 + noise_ * unit(rng_)) + 0.2 * noise_ * delta.x * unit(rng_);
    return geometry::compose(odom, delta);
  }

 private:
  std::mt19937_64 rng_;
  double noise_;
};

// The scan the tests' robot sees: 181 beams over 180 deg, 8 m, 1 cm noise, the laser 0.2 m ahead
// of the base centre.
inline msgs::LaserScan room_scan(const Room& room, const geometry::Pose2D& base,
                                 std::mt19937* rng) {
  estimation_sim::ScanSpec spec;
  spec.beams = 181;
  spec.fov_rad = std::numbers::pi;
  spec.range_max_m = 8.0;
  spec.range_sigma_m = 0.01;
  return estimation_sim::simulate_scan(room.walls, base, {0.2, 0.0, 0.0}, spec, rng);
}

inline double position_error(const geometry::Pose2D& a, const geometry::Pose2D& b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

}  // namespace mobot::pf_world
