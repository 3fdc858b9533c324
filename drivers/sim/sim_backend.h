#pragma once

#include <filesystem>
#include <memory>

#include "drivers/backend.h"
#include "drivers/backend_factory.h"
#include "drivers/sim/sim_camera.h"
#include "drivers/sim/sim_pan_tilt.h"
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
  void advance(double dt_s) override;
  drivers::SimControl* sim_control() override { return this; }

  geometry::Pose2D true_pose() const override { return simulator_->true_pose(); }
  void teleport(const geometry::Pose2D& pose) override { simulator_->teleport(pose); }
  int collision_count() const override { return simulator_->collision_count(); }
  std::optional<double> true_steering_rad() const override {
    if (!profile_.steering) return std::nullopt;
    return simulator_->steering_rad();
  }
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
  int add_target(const MovingTargetSpec& spec) override { return simulator_->add_target(spec); }
  bool remove_target(int id) override { return simulator_->remove_target(id); }

  Simulator& simulator() { return *simulator_; }
  const RobotProfile& profile() const { return profile_; }

 private:
  const RobotProfile profile_;
  const kinematics::RobotGeometry geometry_;
  const std::filesystem::path worlds_dir_;
  std::uint64_t seed_;
  // What the cameras see of the static world, shared with the frames being rendered (they may
  // outlive a reset that replaces the Simulator).
  struct StaticScene {
    World world;
    RayCaster walls;
  };
  void make_cameras();
  // A frame's render job: a copy of the dynamic scene and the camera's pose now.
  SimCamera::RenderJob pan_tilt_frame();
  SimCamera::RenderJob omni_frame();
  // The camera noise's gain drift up to now and the seed for this frame's pixel noise.
  std::uint64_t next_noise(double now_s);

  std::unique_ptr<Simulator> simulator_;
  std::shared_ptr<const StaticScene> scene_;
  SimPanTilt* pan_tilt_ = nullptr;  // owned by drivers_
  std::optional<CameraNoise> camera_noise_;
  std::mt19937_64 camera_rng_;
  double noise_time_s_ = 0.0;
  drivers::DriverSet drivers_;
};

// The profile named in the options ("r1", "dashgo_d1": robot_profiles()), with the options'
// odometry errors, in the world named there. Throws BackendError for an unknown profile, bad
// odometry errors or a world that cannot be loaded.
std::unique_ptr<SimBackend> make_sim_backend(const drivers::BackendOptions& options);

}  // namespace mobot::sim
