#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "drivers/backend.h"

namespace mobot::drivers {

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
};

// A backend that cannot be made as configured; the message names what is wrong.
class BackendError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

std::unique_ptr<Backend> make_backend(const BackendOptions& options);

}  // namespace mobot::drivers
