#pragma once

#include <span>

#include "drivers/sim/moving_target.h"
#include "drivers/sim/ray_caster.h"
#include "drivers/sim/world.h"

namespace mobot::sim {

// A grey cylinder standing on the floor: a dynamic obstacle as the cameras see it (the
// Simulator's Obstacle, without its id).
struct SceneCylinder {
  double x_m = 0.0;
  double y_m = 0.0;
  double radius_m = 0.0;
  double height_m = 0.0;
};

// A moving target where it is at the moment of the frame.
struct SceneSphere {
  double x_m = 0.0;
  double y_m = 0.0;
  double z_m = 0.0;
  double radius_m = 0.0;
  RgbColor color;
};

inline SceneSphere target_sphere(const MovingTarget& target, double time_since_added_s) {
  const geometry::Point2D at = target.position_at(time_since_added_s);
  return {at.x, at.y, target.spec().height_m, target.spec().radius_m, target.spec().color};
}

struct CameraSceneOptions {
  // The floor plan's walls are drawn this tall, and the ceiling (if any) at this height: cameras
  // are assumed to be below it.
  double wall_height_m = 2.5;
  bool ceiling = true;  // false: sky above the walls
  // The landmarks (E2's red lit cylinders of d = 10 cm) as the cameras see them.
  double landmark_radius_m = 0.05;
  double landmark_height_m = 1.5;
  double floor_tile_m = 0.5;  // side of the floor's checker tiles
  double max_range_m = 60.0;  // walls further away are not drawn
};

// What the cameras see, borrowed for one frame: the world's walls (full height, from its floor
// grid), boxes and landmarks, the dynamic obstacles, and the moving targets at their positions.
// The robot's own body is not drawn.
struct CameraScene {
  const World& world;
  // A RayCaster over world.floor alone (the Simulator keeps one for the nodding laser), so that
  // a frame does not pay for building one.
  const RayCaster& walls;
  std::span<const SceneCylinder> obstacles;
  std::span<const SceneSphere> targets;
  CameraSceneOptions options;
};

}  // namespace mobot::sim
