#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "api/ports/result.h"
#include "core/geometry/pose2d.h"

namespace mobot::api {

struct WorldInfo {
  std::string name;
  std::string description;
};

struct SimTruth {
  double t_s = 0.0;
  geometry::Pose2D pose;
  int collisions = 0;
};

struct SimResetRequest {
  std::optional<std::string> world;
  std::optional<geometry::Pose2D> pose;
  std::optional<std::uint64_t> seed;
};

struct SimObstacleRequest {
  double x_m = 0.0;
  double y_m = 0.0;
  double radius_m = 0.0;
  double height_m = 0.0;
};

// The simulator's controls; exists only with the sim backend. Thread-safe.
class SimControlPort {
 public:
  virtual ~SimControlPort() = default;

  virtual std::vector<WorldInfo> list_worlds() const = 0;
  virtual SimTruth sim_truth() const = 0;
  // kInvalid unknown_world / pose_in_obstacle. Completes once the reset event is on disk.
  virtual void sim_reset(const SimResetRequest& request, Completion<Done> done) = 0;
  virtual void set_time_scale(double time_scale) = 0;
  // The new obstacle's id; kInvalid invalid_obstacle.
  virtual void add_sim_obstacle(const SimObstacleRequest& request, Completion<int> done) = 0;
  // kNotFound unknown_obstacle.
  virtual void remove_sim_obstacle(int id, Completion<Done> done) = 0;
  // Moves the simulated robot without telling localization. kInvalid pose_in_obstacle.
  virtual void kidnap(const geometry::Pose2D& pose, Completion<Done> done) = 0;
};

}  // namespace mobot::api
