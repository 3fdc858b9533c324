#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "api/ports/result.h"
#include "core/geometry/pose2d.h"
#include "core/kinematics/robot_geometry.h"
#include "core/msgs/twist.h"
#include "core/navigation/goal.h"

namespace mobot::api {

struct SensorHealth {
  bool ok = false;
  double rate_hz = 0.0;
  std::string reason;  // why it is not ok: "stale", a driver's fault
};

struct RobotSnapshot {
  double t_s = 0.0;
  std::string mode;  // idle | teleop | navigating | mapping | estop
  geometry::Pose2D pose;
  msgs::Twist velocity;
  std::string localization_method;
  std::array<double, 9> covariance{};
  bool localization_converged = false;
  std::string kinematics;
  std::optional<double> steering_rad;  // a steered base's, as commanded
  kinematics::RobotGeometry geometry;
  bool estop = false;
  std::map<std::string, SensorHealth> sensors;
};

struct GoalRequest {
  geometry::Pose2D target;
  bool has_heading = false;
  std::string planner = "astar";
  std::string controller = "lyapunov";
};

// Driving the robot: teleop, e-stop, goals, the localization pose. Reads come from the state the
// control loop publishes each tick and never wait; commands run on the control loop and complete
// once their events are committed. Every method is thread-safe.
class ControlPort {
 public:
  virtual ~ControlPort() = default;

  virtual RobotSnapshot snapshot() const = 0;
  virtual double time_s() const = 0;

  // The command as clamped to the robot's limits; kConflict estop_engaged under e-stop.
  virtual void teleop(const msgs::Twist& command, int ttl_ms, Completion<msgs::Twist> done) = 0;
  // The e-stop state after the request, once its event is on disk.
  virtual void set_estop(bool engaged, Completion<bool> done) = 0;

  // Plans and starts a goal, preempting the active one. kConflict estop_engaged / no_map,
  // kInvalid invalid_pose, kImpossible goal_outside_map / goal_in_obstacle / no_path /
  // start_in_obstacle / start_outside_map.
  virtual void submit_goal(const GoalRequest& request, Completion<navigation::Goal> done) = 0;
  virtual std::vector<navigation::Goal> list_goals() const = 0;
  virtual std::optional<navigation::Goal> find_goal(std::int64_t id) const = 0;
  // kNotFound unknown_goal; kConflict goal_finished.
  virtual void cancel_goal(std::int64_t id, Completion<navigation::Goal> done) = 0;
  // Re-initialises localization at `pose` with a covariance (row-major 3x3).
  virtual void set_localization_pose(const geometry::Pose2D& pose,
                                     const std::array<double, 9>& covariance,
                                     Completion<Done> done) = 0;

  // The names the runtime's registries know, for validating requests.
  virtual std::vector<std::string> planner_names() const = 0;
  virtual std::vector<std::string> controller_names() const = 0;
  // The controller a goal that names none gets.
  virtual std::string default_controller() const { return "lyapunov"; }
  virtual std::string default_planner() const { return "astar"; }
};

}  // namespace mobot::api
