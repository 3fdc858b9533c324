#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "api/robot_port.h"
#include "api/stream_hub.h"
#include "core/control/command_mux.h"
#include "core/control/velocity_smoother.h"
#include "core/navigation/goal.h"
#include "core/perception/obstacle_layer_3d.h"
#include "core/safety/sensor_watchdog.h"
#include "drivers/sim/simulator.h"
#include "drivers/sim/world.h"
#include "server/config.h"
#include "server/localization.h"
#include "server/navigation.h"
#include "server/rate_schedule.h"
#include "server/recorder.h"
#include "server/sweep_scanner.h"

namespace mobot::server {

// The robot runtime of one control period: drivers -> odometry -> command mux -> smoother ->
// base, publishing on the stream hub and the recorder. tick() runs on the control loop's thread;
// the command methods are called from network threads. One mutex guards the state: a tick takes
// well under a millisecond, so a REST call waits at most that long.
class Robot {
 public:
  Robot(const Config& config, sim::World world, api::StreamHub& hub, Recorder& recorder);

  // One control period: advances the simulator by period_s() of robot time.
  void tick();
  double period_s() const { return period_s_; }

  msgs::Twist teleop(const msgs::Twist& command, int ttl_ms);  // ApiError 409 under e-stop
  // Plans (off the control loop) and starts a goal, preempting the active one. ApiError: 409
  // estop_engaged, 422 goal_outside_map / goal_in_obstacle / no_path.
  navigation::Goal submit_goal(const GoalRequest& request);
  std::vector<navigation::Goal> goals() const;
  std::optional<navigation::Goal> goal(std::int64_t id) const;
  // ApiError 404 unknown_goal; a finished goal is returned as it is.
  navigation::Goal cancel_goal(std::int64_t id);
  void set_localization_pose(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance);
  // The active map: localization's wall lines and planning's inflated grid; ends a running goal.
  void set_map(const mapping::OccupancyGrid& map);
  bool set_estop(bool engaged);
  api::RobotSnapshot snapshot() const;
  // The robot clock, without building a snapshot.
  double time_s() const;
  api::SimTruth truth() const;
  // Restarts the simulation in `world` (or the current one) at `pose` (or the world's start).
  void reset(std::optional<sim::World> world, std::optional<geometry::Pose2D> pose,
             std::optional<std::uint64_t> seed);
  bool pose_is_free(const geometry::Pose2D& pose) const;
  int add_obstacle(double x_m, double y_m, double radius_m, double height_m);
  bool remove_obstacle(int id);
  // 3D sweeps. The listener hears every sweep's outcome, on the control loop's thread and under
  // the Robot's mutex: it must hand the outcome on, not call back into the Robot.
  void set_sweep_listener(std::function<void(SweepOutcome)> listener);
  // Starts the sweep at the next tick and returns the robot time it starts at. ApiError 409
  // sweep_running while one runs.
  double start_sweep(std::int64_t id, const perception::SweepMode& mode);
  std::optional<SweepProgress> sweep_progress() const;
  // The 3D-obstacle layer's cell corners, for IPaBD to compute on the same lattice.
  geometry::Point2D obstacle_lattice() const;
  // Merges an IPaBD result (undilated: planning inflates) into the 3D-obstacle layer and plans on
  // it from now on. Returns the layer's occupied cells, or nullopt when the active map is no
  // longer the one of `map_generation` (SweepOutcome::map_generation) and the result was dropped.
  std::optional<int> apply_3d_obstacles(const mapping::OccupancyGrid& observed,
                                        std::uint64_t map_generation);

  // Zero command at once, bypassing the smoother: used on shutdown.
  void halt();
  std::string world_name() const;
  double distance_m() const;
  std::string metrics_text() const;

 private:
  void read_sensors();
  void scan_sweep();
  void end_sweep(std::optional<SweepOutcome> outcome);
  void navigate();
  void publish_goal_changes();
  void check_faults();
  void drive();
  void publish();
  // Forgets every pending command and halts the smoother (the caller holds the mutex).
  void drop_commands();
  void record_event(const std::string& kind, const nlohmann::json& detail);
  std::string mode() const;
  api::RobotSnapshot snapshot_locked() const;
  void start_estimation(const geometry::Pose2D& pose);

  const Config config_;
  api::StreamHub& hub_;
  Recorder& recorder_;
  const double period_s_;

  mutable std::mutex mutex_;
  std::unique_ptr<sim::Simulator> sim_;
  std::uint64_t seed_;
  Localization localization_;
  Navigation navigation_;
  bool navigation_was_active_ = false;
  control::CommandMux mux_;
  control::VelocitySmoother smoother_;
  safety::SensorWatchdog watchdog_;

  // The robot clock: advances one period per tick and never goes back, not even when the
  // simulator restarts (its own clock does), so the trajectory, the watchdog and the stream
  // stamps stay monotonic across a sim reset.
  double now_s_ = 0.0;
  bool estop_ = false;
  bool teleop_was_active_ = false;
  msgs::Twist last_teleop_;
  std::vector<std::string> stale_sensors_;
  RateSchedule laser_schedule_;
  RateSchedule sonar_schedule_;
  RateSchedule compass_schedule_;
  RateSchedule status_schedule_;
  RateSchedule sample_schedule_;
  double distance_before_reset_m_ = 0.0;
  std::optional<msgs::LaserScan> new_scan_;
  std::optional<msgs::SonarRing> new_sonar_;
  std::optional<msgs::CompassReading> compass_;
  SweepScanner sweep_scanner_;
  std::function<void(SweepOutcome)> sweep_listener_;
  perception::ObstacleLayer3D obstacle_layer_;
  std::uint64_t map_generation_ = 0;
  std::uint64_t ticks_ = 0;
  std::uint64_t collisions_ = 0;
};

}  // namespace mobot::server
