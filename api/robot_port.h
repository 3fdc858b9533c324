#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "core/msgs/twist.h"
#include "core/navigation/goal.h"
#include "core/perception/point_cloud.h"

namespace mobot::api {

// The one door from the API into the robot. The server implements it; the API never sees the
// server's classes. Methods are called from network threads and must be thread-safe. A refused
// request throws ApiError and changes nothing.

enum class Role { kViewer = 0, kOperator = 1, kAdmin = 2 };

struct SensorHealth {
  bool ok = false;
  double rate_hz = 0.0;
};

struct RobotSnapshot {
  double t_s = 0.0;
  std::string mode;  // idle | teleop | navigating | mapping | estop
  geometry::Pose2D pose;
  msgs::Twist velocity;
  std::string localization_method;
  std::array<double, 9> covariance{};
  std::string kinematics;
  bool estop = false;
  std::map<std::string, SensorHealth> sensors;
};

struct MapInfo {
  std::int64_t id = 0;
  std::string name;
  int width = 0;
  int height = 0;
  double resolution_m = 0.0;
  geometry::Pose2D origin;
  double created_unix_s = 0.0;
  bool active = false;
};

struct RunInfo {
  std::int64_t id = 0;
  std::string name;
  double started_unix_s = 0.0;
  std::optional<double> ended_unix_s;
  double distance_m = 0.0;
  int goals_succeeded = 0;
  int goals_failed = 0;
  int goals_canceled = 0;
};

struct TrajectoryPoint {
  double t_s, x, y, theta;
};

struct RunEvent {
  double t_s = 0.0;
  std::string kind;
  std::string detail_json;
};

struct TokenInfo {
  std::int64_t id = 0;
  Role role = Role::kViewer;
  std::string label;
  double created_unix_s = 0.0;
  bool revoked = false;
};

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

struct GoalRequest {
  geometry::Pose2D target;
  bool has_heading = false;
  std::string planner = "astar";
  std::string controller = "lyapunov";
};

struct SweepRequest {
  double period_s = 10.0;  // 10 | 42
  double step_deg = 1.0;   // 1 | 0.5 | 0.25
};

struct SweepInfo {
  std::int64_t id = 0;
  std::string status;  // running | done | failed
  std::string reason;  // why it failed
  double period_s = 0.0;
  double step_deg = 0.0;
  int scans = 0;
  int scans_done = 0;
  std::int64_t points = 0;
  double started_t = 0.0;
  std::optional<double> ended_t;
};

class RobotPort {
 public:
  virtual ~RobotPort() = default;

  virtual std::optional<Role> authenticate(std::string_view token) = 0;

  virtual std::string backend_name() const = 0;
  virtual double uptime_s() const = 0;
  virtual RobotSnapshot snapshot() const = 0;

  // Returns the command as clamped to the robot's limits. 409 estop_engaged under e-stop.
  virtual msgs::Twist teleop(const msgs::Twist& command, int ttl_ms) = 0;
  virtual bool set_estop(bool engaged) = 0;

  // Plans and starts a goal (preempting the active one). ApiError 409 estop_engaged, 422
  // goal_outside_map / goal_in_obstacle / no_path / unsupported_planner / unsupported_controller.
  virtual navigation::Goal submit_goal(const GoalRequest& request) = 0;
  virtual std::vector<navigation::Goal> list_goals() const = 0;
  virtual std::optional<navigation::Goal> find_goal(std::int64_t id) const = 0;
  virtual navigation::Goal cancel_goal(std::int64_t id) = 0;  // 404 unknown_goal
  // Re-initialises localization at `pose` with a covariance (row-major 3x3).
  virtual void set_localization_pose(const geometry::Pose2D& pose,
                                     const std::array<double, 9>& covariance) = 0;

  virtual std::vector<MapInfo> list_maps() const = 0;
  virtual std::optional<MapInfo> map_info(std::int64_t id) const = 0;
  virtual std::optional<mapping::OccupancyGrid> map_grid(std::int64_t id) const = 0;
  virtual std::int64_t import_map(const std::string& name, const mapping::OccupancyGrid& grid) = 0;
  virtual void activate_map(std::int64_t id) = 0;  // 404 unknown_map
  virtual void delete_map(std::int64_t id) = 0;    // 404 unknown_map, 409 map_active

  virtual std::vector<RunInfo> list_runs() const = 0;
  virtual std::optional<std::vector<TrajectoryPoint>> run_trajectory(std::int64_t id) const = 0;
  virtual std::optional<std::vector<RunEvent>> run_events(std::int64_t id) const = 0;

  // Token management (admin). create_token returns the id and the plain token, shown only once.
  virtual std::pair<std::int64_t, std::string> create_token(Role role, const std::string& label) = 0;
  virtual std::vector<TokenInfo> list_tokens() const = 0;
  virtual bool revoke_token(std::int64_t id) = 0;

  // 3D sweeps. start_sweep: ApiError 400 invalid_mode (not a Table 2.1 mode), 409 sweep_running.
  virtual SweepInfo start_sweep(const SweepRequest& request) = 0;
  virtual std::vector<SweepInfo> list_sweeps() const = 0;
  virtual std::optional<SweepInfo> find_sweep(std::int64_t id) const = 0;
  // ApiError 404 unknown_sweep, 409 sweep_not_done (running or failed).
  virtual perception::PointCloud sweep_cloud(std::int64_t id) const = 0;
  virtual mapping::OccupancyGrid sweep_obstacle_map(std::int64_t id) const = 0;
  // Deletes a finished sweep's record, cloud and map (the 3D layer keeps what it merged).
  // ApiError 404 unknown_sweep, 409 sweep_running.
  virtual void delete_sweep(std::int64_t id) = 0;

  virtual bool is_simulated() const = 0;
  // The simulator endpoints; only called when is_simulated().
  virtual std::vector<WorldInfo> list_worlds() const = 0;
  virtual SimTruth sim_truth() const = 0;
  virtual void sim_reset(const SimResetRequest& request) = 0;  // 400 unknown_world / pose_in_obstacle
  virtual void set_time_scale(double time_scale) = 0;
  virtual int add_sim_obstacle(double x_m, double y_m, double radius_m, double height_m) = 0;
  virtual bool remove_sim_obstacle(int id) = 0;

  // The robot side's Prometheus metrics (control loop, sensors, recorder), in text format.
  virtual std::string metrics_text() const = 0;
};

}  // namespace mobot::api
