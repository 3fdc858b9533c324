#include "tools/emulate/floor_plan_world.h"

#include "drivers/sim/world_slice.h"

namespace mobot::emulate {

FloorPlanWorld::FloorPlanWorld(sim::World world) : world_(std::move(world)), pose_(world_.start) {}

std::optional<double> FloorPlanWorld::cast_ray(geometry::Point2D from, double angle_rad,
                                               double height_m, double max_range_m) const {
  auto& caster = casters_[height_m];
  if (!caster) {
    caster = std::make_unique<sim::RayCaster>(sim::slice_at_height(world_, height_m));
  }
  return caster->cast(from, angle_rad, max_range_m);
}

}  // namespace mobot::emulate
