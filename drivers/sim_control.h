#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "drivers/sim/moving_target.h"

namespace mobot::sim {
struct World;
}

namespace mobot::drivers {

struct SimWorldEntry {
  std::string name;
  std::string description;
};

// A world a reset may switch to, loaded (file I/O, off the control loop) before the reset.
struct SimWorldChoice {
  std::string name;
  mapping::OccupancyGrid surveyed_map;  // the floor plan as a map at the robot's height
  std::shared_ptr<const sim::World> world;
};

// What only a simulated robot offers: the truth, resets, obstacles dropped at run time. Exists
// only with the sim backend. Called on the control loop, except where a method says otherwise.
class SimControl {
 public:
  virtual ~SimControl() = default;

  virtual geometry::Pose2D true_pose() const = 0;
  virtual int collision_count() const = 0;
  // A steered base's true steering angle; nothing for a differential base.
  virtual std::optional<double> true_steering_rad() const { return std::nullopt; }
  virtual std::string world_name() const = 0;
  // The current world's floor plan as a map at the robot's height.
  virtual mapping::OccupancyGrid surveyed_map() const = 0;

  // Any thread: the built-in and configured worlds, and loading one for a reset (file I/O;
  // throws std::invalid_argument with the reason when it cannot be loaded).
  virtual std::vector<SimWorldEntry> worlds() const = 0;
  virtual SimWorldChoice load_world(const std::string& name) const = 0;
  // Whether the robot's body fits at `pose` in `world`, or in the current world when null (on
  // the control loop only then).
  virtual bool pose_is_free(const geometry::Pose2D& pose,
                            const SimWorldChoice* world = nullptr) const = 0;

  // Restarts the simulation in `world` (the current one when null) at `pose` (the world's start
  // when null), reseeded when `seed` is given.
  virtual void reset(const SimWorldChoice* world, std::optional<geometry::Pose2D> pose,
                     std::optional<std::uint64_t> seed) = 0;
  virtual std::uint64_t seed() const = 0;
  // Moves the robot to `pose` behind localization's back (no encoder counts; the caller checks
  // pose_is_free first).
  virtual void teleport(const geometry::Pose2D& pose) = 0;
  // Returns the id; std::invalid_argument for a radius or height that is not positive and finite.
  virtual int add_obstacle(double x_m, double y_m, double radius_m, double height_m) = 0;
  virtual bool remove_obstacle(int id) = 0;
  // A coloured ball the cameras see (sim::MovingTarget's checks: std::invalid_argument naming
  // the field); its id.
  virtual int add_target(const sim::MovingTargetSpec& spec) = 0;
  virtual bool remove_target(int id) = 0;
};

}  // namespace mobot::drivers
