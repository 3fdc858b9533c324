#include "drivers/sim/tilted_fan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "core/numeric/constants.h"
#include "drivers/sim/simulator.h"

namespace mobot::sim {
namespace {

// Distance along the 3D ray to a vertical cylinder standing on the floor: its side, or its top
// for a ray coming down onto it. Negative when missed.
double ray_cylinder_distance(const double origin[3], const double direction[3],
                             const Obstacle& obstacle) {
  const double horizontal = std::hypot(direction[0], direction[1]);
  double best = kInfinity;
  if (horizontal > 1e-12) {
    const double heading_rad = std::atan2(direction[1], direction[0]);
    const auto side = cast_to_circle({origin[0], origin[1]}, heading_rad,
                                     {obstacle.x_m, obstacle.y_m}, obstacle.radius_m);
    if (side) {
      const double t = *side / horizontal;
      const double z = origin[2] + t * direction[2];
      if (z >= 0.0 && z <= obstacle.height_m) best = t;
    }
  }
  if (direction[2] < 0.0 && origin[2] > obstacle.height_m) {
    const double t = (obstacle.height_m - origin[2]) / direction[2];
    const double x = origin[0] + t * direction[0] - obstacle.x_m;
    const double y = origin[1] + t * direction[1] - obstacle.y_m;
    if (x * x + y * y <= obstacle.radius_m * obstacle.radius_m) best = std::min(best, t);
  }
  return best == kInfinity ? -1.0 : best;
}

}  // namespace

float surface_intensity(Surface surface) {
  switch (surface) {
    case Surface::kFloor:
      return 0.25F;
    case Surface::kWall:
      return 0.55F;
    case Surface::kBox:
      return 0.85F;
    case Surface::kObstacle:
      return 0.7F;
    case Surface::kNone:
      break;
  }
  return 0.0F;
}

double ray_box_distance(const double origin[3], const double direction[3], const Box3D& box) {
  const double low[3] = {box.min_x_m, box.min_y_m, box.min_z_m};
  const double high[3] = {box.max_x_m, box.max_y_m, box.max_z_m};
  double enter = 0.0;
  double leave = kInfinity;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(direction[axis]) < 1e-12) {
      if (origin[axis] < low[axis] || origin[axis] > high[axis]) return -1.0;
      continue;
    }
    double t0 = (low[axis] - origin[axis]) / direction[axis];
    double t1 = (high[axis] - origin[axis]) / direction[axis];
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
    if (enter > leave) return -1.0;
  }
  return enter;
}

void cast_tilted_fan(const TiltedFan& fan, const RayCaster& walls, std::span<const Box3D> boxes,
                     std::span<const Obstacle> obstacles, std::span<double> ranges_m,
                     std::span<Surface> surfaces) {
  const double cos_pitch = std::cos(fan.pitch_rad);
  const double sin_pitch = std::sin(fan.pitch_rad);
  // The walls reach from floor to ceiling, so the beam meets them where its horizontal trace does.
  const double first_heading_rad = fan.sensor.theta + fan.first_bearing_rad - std::numbers::pi / 2;
  std::vector<double> wall_horizontal_m(ranges_m.size());
  walls.cast_fan({fan.sensor.x, fan.sensor.y}, first_heading_rad, fan.step_rad,
                 fan.max_range_m * cos_pitch, wall_horizontal_m);
  const double floor_m = sin_pitch < 0.0 ? fan.height_m / -sin_pitch : kInfinity;
  const double origin[3] = {fan.sensor.x, fan.sensor.y, fan.height_m};
  for (std::size_t k = 0; k < ranges_m.size(); ++k) {
    const double heading_rad = first_heading_rad + static_cast<double>(k) * fan.step_rad;
    const double direction[3] = {cos_pitch * std::cos(heading_rad),
                                 cos_pitch * std::sin(heading_rad), sin_pitch};
    double nearest_m = floor_m;
    Surface surface = Surface::kFloor;
    if (std::isfinite(wall_horizontal_m[k]) && wall_horizontal_m[k] / cos_pitch < nearest_m) {
      nearest_m = wall_horizontal_m[k] / cos_pitch;
      surface = Surface::kWall;
    }
    for (const Box3D& box : boxes) {
      const double t = ray_box_distance(origin, direction, box);
      if (t >= 0.0 && t < nearest_m) {
        nearest_m = t;
        surface = Surface::kBox;
      }
    }
    for (const Obstacle& obstacle : obstacles) {
      const double t = ray_cylinder_distance(origin, direction, obstacle);
      if (t >= 0.0 && t < nearest_m) {
        nearest_m = t;
        surface = Surface::kObstacle;
      }
    }
    if (nearest_m > fan.max_range_m) {
      nearest_m = kInfinity;
      surface = Surface::kNone;
    }
    ranges_m[k] = nearest_m;
    surfaces[k] = surface;
  }
}

}  // namespace mobot::sim
