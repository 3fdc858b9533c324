#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/geometry/pose2d.h"
#include "drivers/sim/oriented_rect.h"
#include "drivers/sim/world.h"

namespace mobot::sim {

// The robot's body against the static world in 3D: a box of footprint_length x footprint_width
// centred offset_m ahead of the base origin, from the floor up to height_m. Walls of the floor plan are full
// height; a box collides when its z range overlaps [0, height_m], so a robot passes under a beam
// only when the beam's underside is above the robot.
class BodyCollider {
 public:
  BodyCollider(const World& world, double footprint_length_m, double footprint_width_m,
               double height_m, double offset_m = 0.0);

  // What the body would touch at `pose`: "wall" (also for leaving the floor plan) or a box's name;
  // nullopt when the pose is free.
  std::optional<std::string> contact(const geometry::Pose2D& pose) const;

  OrientedRect footprint_at(const geometry::Pose2D& pose) const;

 private:
  bool touches_wall(const OrientedRect& footprint) const;
  // True when no wall cell can reach a footprint centred in `cell` (cell in grid coordinates).
  bool clear_of_walls(int x, int y) const;

  mapping::OccupancyGrid floor_;
  double half_length_m_;
  double half_width_m_;
  double offset_m_;
  // Per cell, with a ring of wall cells around the map (leaving it counts as a wall): the distance
  // in cells between its centre and the nearest wall cell's centre. Lets the common case, a robot
  // in open space, skip looking at the cells under it.
  std::vector<float> wall_distance_cells_;
  double half_diagonal_m_;
  std::vector<Box3D> boxes_;  // only those reaching into the body's height
};

}  // namespace mobot::sim
