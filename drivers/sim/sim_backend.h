#pragma once

#include <filesystem>
#include <memory>

#include "drivers/backend.h"
#include "drivers/backend_factory.h"
#include "drivers/sim/simulator.h"

namespace mobot::sim {

// The simulated robot as a backend: one Simulator, and drivers for its base and sensors that
// read it as the real devices would be read. A reset to another world replaces the Simulator;
// the drivers reach it through simulator(), so they never hold a stale one.
class SimBackend final : public drivers::Backend, public drivers::SimControl {
 public:
  SimBackend(World world, RobotProfile profile, const drivers::BackendOptions& options);

  std::string_view name() const override { return "sim"; }
  const kinematics::RobotGeometry& geometry() const override { return geometry_; }
  drivers::DriverSet& drivers() override { return drivers_; }
  void advance(double dt_s) override { simulator_->step(dt_s); }
  drivers::SimControl* sim_control() override { return this; }

  geometry::Pose2D true_pose() const override { return simulator_->true_pose(); }
  void teleport(const geometry::Pose2D& pose) override { simulator_->teleport(pose); }
  int collision_count() const override { return simulator_->collision_count(); }
  std::string world_name() const override { return simulator_->world().name; }
  mapping::OccupancyGrid surveyed_map() const override;
  std::vector<drivers::SimWorldEntry> worlds() const override;
  drivers::SimWorldChoice load_world(const std::string& name) const override;
  bool pose_is_free(const geometry::Pose2D& pose,
                    const drivers::SimWorldChoice* world) const override;
  void reset(const drivers::SimWorldChoice* world, std::optional<geometry::Pose2D> pose,
             std::optional<std::uint64_t> seed) override;
  std::uint64_t seed() const override { return seed_; }
  int add_obstacle(double x_m, double y_m, double radius_m, double height_m) override;
  bool remove_obstacle(int id) override { return simulator_->remove_obstacle(id); }

  Simulator& simulator() { return *simulator_; }
  const RobotProfile& profile() const { return profile_; }

 private:
  const RobotProfile profile_;
  const kinematics::RobotGeometry geometry_;
  const std::filesystem::path worlds_dir_;
  std::uint64_t seed_;
  std::unique_ptr<Simulator> simulator_;
  drivers::DriverSet drivers_;
};

// The profile named in the options ("r1", "dashgo_d1": robot_profiles()), with the options'
// odometry errors, in the world named there. Throws BackendError for an unknown profile, bad
// odometry errors or a world that cannot be loaded.
std::unique_ptr<SimBackend> make_sim_backend(const drivers::BackendOptions& options);

}  // namespace mobot::sim
