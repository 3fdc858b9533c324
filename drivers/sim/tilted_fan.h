#pragma once

#include <cstdint>
#include <span>

#include "core/geometry/pose2d.h"
#include "drivers/sim/ray_caster.h"
#include "drivers/sim/world.h"

namespace mobot::sim {

struct Obstacle;

// What a beam of the nodding laser met; the simulator's reflectance model reads it.
enum class Surface : std::uint8_t { kNone, kFloor, kWall, kBox, kObstacle };

// Reflectance the simulated laser reports per surface (0..1): enough for a cloud coloured by
// intensity to tell the floor, walls and furniture apart.
float surface_intensity(Surface surface);

// A fan of beams in a plane pitched up by pitch_rad, from a sensor at `sensor` (map frame, heading
// = the fan's middle beam) and height_m above the floor. Beam k has bearing first_bearing_rad +
// k * step_rad, pi/2 being straight ahead (P1). Walls (the floor plan, full height) come from
// `walls`; the floor is z = 0; boxes and obstacles are solids in 3D.
struct TiltedFan {
  geometry::Pose2D sensor;
  double height_m = 0.0;
  double pitch_rad = 0.0;
  double first_bearing_rad = 0.0;
  double step_rad = 0.0;
  double max_range_m = 0.0;
};

// Fills ranges_m (3D distance to the first surface, +infinity when none within max_range_m) and
// surfaces, one per element of ranges_m.
void cast_tilted_fan(const TiltedFan& fan, const RayCaster& walls, std::span<const Box3D> boxes,
                     std::span<const Obstacle> obstacles, std::span<double> ranges_m,
                     std::span<Surface> surfaces);

// Distance along a 3D ray (unit direction) to an axis-aligned box, or a negative value when the
// ray misses it. A ray starting inside hits at 0.
double ray_box_distance(const double origin[3], const double direction[3], const Box3D& box);

}  // namespace mobot::sim
