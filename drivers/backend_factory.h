#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include <yaml-cpp/yaml.h>

#include "drivers/backend.h"

namespace mobot::drivers {

// The simulated odometry errors of the config's sim.odometry (docs/algorithms.md R2); an unset
// field keeps the robot profile's own value.
struct SimOdometryErrors {
  std::optional<double> scale_error;
  std::optional<double> heading_drift_rad_per_m;
  std::optional<double> step_noise_fraction;

  bool any() const { return scale_error || heading_drift_rad_per_m || step_noise_fraction; }
};

// What the config says about the devices.
struct BackendOptions {
  std::string backend = "sim";  // sim | hardware
  std::string profile = "r1";   // the robot the devices belong to
  // The simulator's world (a built-in name or a world.yaml) and where the built-ins live.
  std::string world = "office";
  std::filesystem::path worlds_dir;
  std::uint64_t seed = 1;
  double laser_rate_hz = 10.0;
  double sonar_rate_hz = 10.0;
  double compass_rate_hz = 10.0;
  SimOdometryErrors odometry_errors;
  // R1's omni camera as rendered pixels (landmark bearings from the image) rather than geometry.
  bool omni_pixels = false;
  // The real devices (`--backend hardware`): the config's hardware section, one entry per role
  // (base, laser, ir, tilt, bus, camera), each {driver, device, baud, ...}.
  YAML::Node hardware;
  // The base is polled at the control loop's rate.
  double control_rate_hz = 50.0;
};

// A backend that cannot be made as configured; the message names what is wrong.
class BackendError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

std::unique_ptr<Backend> make_backend(const BackendOptions& options);

}  // namespace mobot::drivers
