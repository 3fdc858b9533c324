#pragma once

#include <map>
#include <memory>

#include "drivers/sim/ray_caster.h"
#include "drivers/sim/world.h"
#include "tools/emulate/emulated_world.h"

namespace mobot::emulate {

// The emulated robot's surroundings: a simulator world (its floor plan and 3D boxes), seen at
// each sensor's height as the simulator's own sensors see it.
class FloorPlanWorld final : public EmulatedWorld {
 public:
  explicit FloorPlanWorld(sim::World world);

  geometry::Pose2D base_pose() const override { return pose_; }
  void set_base_pose(const geometry::Pose2D& pose) override { pose_ = pose; }
  std::optional<double> cast_ray(geometry::Point2D from, double angle_rad, double height_m,
                                 double max_range_m) const override;
  const sim::World& world() const { return world_; }

 private:
  sim::World world_;
  geometry::Pose2D pose_;
  // One caster per height asked for (a handful: laser, sonar, IR), built on first use.
  mutable std::map<double, std::unique_ptr<sim::RayCaster>> casters_;
};

}  // namespace mobot::emulate
