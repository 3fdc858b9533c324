#include "drivers/sim/sim_backend.h"

#include "drivers/sim/camera_renderer.h"

#include <stdexcept>

#include "core/safety/sharp_ir_curve.h"
#include "drivers/sim/sim_base.h"
#include "drivers/sim/sim_sensor.h"
#include "drivers/sim/sim_tilt_laser.h"
#include "drivers/sim/world.h"

namespace mobot::sim {
namespace {

std::filesystem::path worlds_dir_of(const drivers::BackendOptions& options) {
  return options.worlds_dir.empty() ? std::filesystem::path(MOBOT_DEFAULT_WORLDS_DIR)
                                    : options.worlds_dir;
}

RobotProfile configured_profile(const drivers::BackendOptions& options) {
  std::optional<RobotProfile> profile = profile_named(options.profile);
  if (!profile) {
    std::string names;
    for (const NamedProfile& entry : robot_profiles()) {
      names += (names.empty() ? "" : ", ") + std::string(entry.name);
    }
    throw drivers::BackendError("robot.profile: the simulator has no '" + options.profile +
                                "' robot; it has " + names);
  }
  if (options.omni_pixels && profile->has_omni_camera) {
    // The omni camera's image is rendered and its bearings found in the pixels, instead of the
    // geometric bearings.
    profile->omni_image = OmniImageProfile{};
    profile->omni_image->rate_hz = options.compass_rate_hz;
    profile->has_omni_camera = false;
  }
  const drivers::SimOdometryErrors& overrides = options.odometry_errors;
  if (overrides.any()) {
    OdometryErrors errors = odometry_errors_of(*profile);
    errors.scale_error = overrides.scale_error.value_or(errors.scale_error);
    errors.heading_drift_rad_per_m =
        overrides.heading_drift_rad_per_m.value_or(errors.heading_drift_rad_per_m);
    errors.step_noise_fraction = overrides.step_noise_fraction.value_or(errors.step_noise_fraction);
    try {
      set_odometry_errors(*profile, errors);
    } catch (const std::invalid_argument& error) {
      throw drivers::BackendError(std::string("sim.odometry: ") + error.what());
    }
  }
  return *profile;
}

// The IR microcontroller's counts through the robot's calibration curve, as the real driver
// converts them.
msgs::IrRing ir_ring_from(const std::vector<int>& counts, const RobotProfile& profile,
                          const safety::SharpIrCurve& curve) {
  msgs::IrRing ring;
  for (std::size_t i = 0; i < counts.size() && i < profile.ir_sensors_in_base.size(); ++i) {
    ring.readings.push_back(
        curve.reading(counts[i], profile.ir_sensors_in_base[i], profile.ir_cone_rad));
  }
  return ring;
}

}  // namespace

SimBackend::SimBackend(World world, RobotProfile profile, const drivers::BackendOptions& options)
    : profile_(std::move(profile)),
      geometry_(geometry_of(profile_)),
      worlds_dir_(worlds_dir_of(options)),
      seed_(options.seed),
      simulator_(std::make_unique<Simulator>(std::move(world), profile_, seed_)) {
  drivers_.base = std::make_unique<SimBase>(*this);
  drivers_.laser = std::make_unique<SimSensor<msgs::LaserScan>>(
      "laser", options.laser_rate_hz, [this] { return simulator_->read_laser(); });
  drivers_.sonar = std::make_unique<SimSensor<msgs::SonarRing>>(
      "sonar", options.sonar_rate_hz, [this] { return simulator_->read_sonar(); });
  if (!profile_.ir_sensors_in_base.empty()) {
    drivers_.ir = std::make_unique<SimSensor<msgs::IrRing>>(
        "ir", profile_.ir_rate_hz, [this, curve = safety::SharpIrCurve(profile_.ir_adc.curve)] {
          return ir_ring_from(simulator_->read_ir_adc(), profile_, curve);
        });
  }
  if (profile_.has_compass) {
    drivers_.compass = std::make_unique<SimSensor<msgs::CompassReading>>(
        "compass", options.compass_rate_hz, [this] { return simulator_->read_compass(); });
  }
  if (profile_.has_omni_camera) {
    // The omni camera's bearings are taken with the compass reading, as R1 reads them together.
    drivers_.bearings = std::make_unique<SimSensor<msgs::LandmarkBearings>>(
        "bearings", options.compass_rate_hz,
        [this] { return simulator_->read_landmark_bearings(); });
  }
  if (profile_.has_tilt_laser) drivers_.tilt = std::make_unique<SimTiltLaser>(*this, seed_);
  make_cameras();
}

void SimBackend::make_cameras() {
  if (!profile_.pan_tilt_camera && !profile_.omni_image) return;
  scene_ = std::make_shared<const StaticScene>(
      StaticScene{simulator_->world(), RayCaster(simulator_->world().floor)});
  // A stream of its own, seeded apart from the Simulator's, so cameras never change how it runs.
  camera_rng_ = std::mt19937_64(seed_ ^ 0x63616d657261ULL);
  if (const auto& camera = profile_.pan_tilt_camera) {
    camera_noise_.emplace(camera->noise);
    camera_noise_->start(camera_rng_);
    auto head = std::make_unique<SimPanTilt>(camera->head);
    pan_tilt_ = head.get();
    drivers_.pan_tilt = std::move(head);
    drivers_.camera = std::make_unique<SimCamera>(camera->rate_hz, camera->jpeg_quality,
                                                  [this] { return pan_tilt_frame(); });
    drivers::CameraInfo info;
    info.kind = "pan_tilt";
    info.pinhole = camera->camera;
    info.rate_hz = camera->rate_hz;
    info.height_m = vision::PanTiltHead(camera->head).lens_in_base({}).z_m;
    info.range_cone_rad = camera->range_cone_rad;
    drivers_.camera_info = info;
    drivers_.head_range = std::make_unique<SimSensor<msgs::HeadRange>>(
        "head_range", camera->range_rate_hz,
        [this] { return simulator_->read_head_range(pan_tilt_->current()); });
    return;
  }
  const OmniImageProfile& omni = *profile_.omni_image;
  camera_noise_.emplace(omni.noise);
  camera_noise_->start(camera_rng_);
  drivers_.camera = std::make_unique<SimCamera>(omni.rate_hz, omni.jpeg_quality,
                                                [this] { return omni_frame(); });
  drivers::CameraInfo info;
  info.kind = "omni";
  info.omni = omni.model;
  for (const Landmark& landmark : simulator_->world().landmarks) {
    info.landmarks.push_back({landmark.name, {landmark.x_m, landmark.y_m}});
  }
  info.landmark_range_m = profile_.camera_range_m;
  info.rate_hz = omni.rate_hz;
  info.height_m = omni.height_m;
  drivers_.camera_info = info;
}

void SimBackend::advance(double dt_s) {
  simulator_->step(dt_s);
  if (pan_tilt_) pan_tilt_->advance(dt_s);
}

std::uint64_t SimBackend::next_noise(double now_s) {
  camera_noise_->advance(std::max(0.0, now_s - noise_time_s_), camera_rng_);
  noise_time_s_ = now_s;
  return camera_rng_();
}

SimCamera::RenderJob SimBackend::pan_tilt_frame() {
  const PanTiltCameraProfile& camera = *profile_.pan_tilt_camera;
  const vision::CameraPose pose = vision::PanTiltHead(camera.head)
                                      .camera_pose(simulator_->true_pose(), pan_tilt_->current());
  const std::uint64_t seed = next_noise(simulator_->time_s());
  return [scene = scene_, obstacles = simulator_->obstacle_cylinders(),
          targets = simulator_->target_spheres(), pose, pinhole = camera.camera,
          noise = *camera_noise_, seed] {
    std::mt19937_64 rng(seed);
    return render_perspective({scene->world, scene->walls, obstacles, targets, {}}, pose, pinhole,
                              noise, rng);
  };
}

SimCamera::RenderJob SimBackend::omni_frame() {
  const OmniImageProfile& omni = *profile_.omni_image;
  const std::uint64_t seed = next_noise(simulator_->time_s());
  return [scene = scene_, obstacles = simulator_->obstacle_cylinders(),
          targets = simulator_->target_spheres(), base = simulator_->true_pose(),
          height_m = omni.height_m, model = omni.model, noise = *camera_noise_, seed] {
    std::mt19937_64 rng(seed);
    return render_omni({scene->world, scene->walls, obstacles, targets, {}}, base, height_m, model,
                       noise, rng);
  };
}

mapping::OccupancyGrid SimBackend::surveyed_map() const {
  return sim::surveyed_map(simulator_->world(), profile_.height_m);
}

std::vector<drivers::SimWorldEntry> SimBackend::worlds() const {
  std::vector<drivers::SimWorldEntry> out;
  for (const auto& world : list_worlds(worlds_dir_)) out.push_back({world.name, world.description});
  return out;
}

drivers::SimWorldChoice SimBackend::load_world(const std::string& name) const {
  try {
    auto world = std::make_shared<const World>(sim::load_world(resolve_world(worlds_dir_, name)));
    return {world->name, sim::surveyed_map(*world, profile_.height_m), world};
  } catch (const WorldError& error) {
    throw std::invalid_argument(error.what());
  }
}

bool SimBackend::pose_is_free(const geometry::Pose2D& pose,
                              const drivers::SimWorldChoice* world) const {
  if (world) return !Simulator(*world->world, profile_, 0).pose_collides(pose);
  return !simulator_->pose_collides(pose);
}

void SimBackend::reset(const drivers::SimWorldChoice* world, std::optional<geometry::Pose2D> pose,
                       std::optional<std::uint64_t> seed) {
  if (seed) seed_ = *seed;
  if (world) {
    const geometry::Pose2D start = pose.value_or(world->world->start);
    simulator_ = std::make_unique<Simulator>(*world->world, profile_, seed_);
    simulator_->reset(start, seed_);
    if (scene_) {
      scene_ = std::make_shared<const StaticScene>(
          StaticScene{simulator_->world(), RayCaster(simulator_->world().floor)});
    }
  } else {
    simulator_->reset(pose.value_or(simulator_->world().start), seed_);
  }
  if (pan_tilt_) pan_tilt_->reset();
  noise_time_s_ = 0.0;
}

int SimBackend::add_obstacle(double x_m, double y_m, double radius_m, double height_m) {
  return simulator_->add_obstacle(x_m, y_m, radius_m, height_m);
}

std::unique_ptr<SimBackend> make_sim_backend(const drivers::BackendOptions& options) {
  RobotProfile profile = configured_profile(options);
  World world;
  try {
    world = load_world(resolve_world(worlds_dir_of(options), options.world));
  } catch (const WorldError& error) {
    throw drivers::BackendError(std::string("world: ") + error.what());
  }
  return std::make_unique<SimBackend>(std::move(world), std::move(profile), options);
}

}  // namespace mobot::sim
