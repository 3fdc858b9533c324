#pragma once

#include <array>
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
  std::optional<double> steering_rad;  // a steered base's true steering angle
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

// A coloured ball the simulated cameras see, moving along a path.
struct SimTargetRequest {
  std::array<int, 3> color{220, 30, 30};  // r, g, b 0..255
  double radius_m = 0.1;
  double height_m = 0.5;  // of its centre above the floor
  std::vector<geometry::Point2D> path;
  double speed_mps = 0.3;
  bool loop = true;
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
  // The new target's id; kInvalid invalid_target.
  virtual void add_sim_target(const SimTargetRequest& request, Completion<int> done) = 0;
  // kNotFound unknown_target.
  virtual void remove_sim_target(int id, Completion<Done> done) = 0;
  // Moves the simulated robot without telling localization. kInvalid pose_in_obstacle.
  virtual void kidnap(const geometry::Pose2D& pose, Completion<Done> done) = 0;
};

}  // namespace mobot::api
