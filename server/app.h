#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include <boost/asio/io_context.hpp>

#include "api/http_server.h"
#include "api/rest_api.h"
#include "api/robot_port.h"
#include "api/stream_hub.h"
#include "db/database.h"
#include "db/map_store.h"
#include "db/run_store.h"
#include "db/sweep_store.h"
#include "db/token_store.h"
#include "server/config.h"
#include "server/control_loop.h"
#include "server/recorder.h"
#include "server/robot.h"
#include "server/sweeps.h"

namespace mobot::server {

// mobotd: wires the store, the robot, the control loop and the HTTP/WebSocket server, and is the
// API's port into the robot.
class App final : public api::RobotPort {
 public:
  explicit App(Config config);
  ~App() override;

  // Listens, prints the ready line, and serves until SIGINT/SIGTERM; returns the exit code.
  int run();

  std::optional<api::Role> authenticate(std::string_view token) override;
  std::string backend_name() const override { return config_.backend; }
  double uptime_s() const override;
  api::RobotSnapshot snapshot() const override { return robot_->snapshot(); }
  msgs::Twist teleop(const msgs::Twist& command, int ttl_ms) override;
  bool set_estop(bool engaged) override;
  navigation::Goal submit_goal(const api::GoalRequest& request) override;
  std::vector<navigation::Goal> list_goals() const override { return robot_->goals(); }
  std::optional<navigation::Goal> find_goal(std::int64_t id) const override {
    return robot_->goal(id);
  }
  navigation::Goal cancel_goal(std::int64_t id) override;
  void set_localization_pose(const geometry::Pose2D& pose,
                             const std::array<double, 9>& covariance) override;

  std::vector<api::MapInfo> list_maps() const override;
  std::optional<api::MapInfo> map_info(std::int64_t id) const override;
  std::optional<mapping::OccupancyGrid> map_grid(std::int64_t id) const override;
  std::int64_t import_map(const std::string& name, const mapping::OccupancyGrid& grid) override;
  void activate_map(std::int64_t id) override;
  void delete_map(std::int64_t id) override;

  std::vector<api::RunInfo> list_runs() const override;
  std::optional<std::vector<api::TrajectoryPoint>> run_trajectory(std::int64_t id) const override;
  std::optional<std::vector<api::RunEvent>> run_events(std::int64_t id) const override;

  std::pair<std::int64_t, std::string> create_token(api::Role role,
                                                    const std::string& label) override;
  std::vector<api::TokenInfo> list_tokens() const override;
  bool revoke_token(std::int64_t id) override;

  api::SweepInfo start_sweep(const api::SweepRequest& request) override {
    return sweeps_->start(request);
  }
  std::vector<api::SweepInfo> list_sweeps() const override { return sweeps_->list(); }
  std::optional<api::SweepInfo> find_sweep(std::int64_t id) const override {
    return sweeps_->find(id);
  }
  perception::PointCloud sweep_cloud(std::int64_t id) const override { return sweeps_->cloud(id); }
  mapping::OccupancyGrid sweep_obstacle_map(std::int64_t id) const override {
    return sweeps_->obstacle_map(id);
  }
  void delete_sweep(std::int64_t id) override { sweeps_->remove(id); }

  bool is_simulated() const override { return config_.backend == "sim"; }
  std::vector<api::WorldInfo> list_worlds() const override;
  api::SimTruth sim_truth() const override { return robot_->truth(); }
  void sim_reset(const api::SimResetRequest& request) override;
  void set_time_scale(double time_scale) override;
  int add_sim_obstacle(double x_m, double y_m, double radius_m, double height_m) override;
  bool remove_sim_obstacle(int id) override;
  std::string metrics_text() const override;

 private:
  void ensure_admin_token();
  void ensure_world_map(const std::string& world_name, const mapping::OccupancyGrid& floor);
  void publish_active_map();
  void shut_down();

  Config config_;
  std::filesystem::path worlds_dir_;
  db::Database database_;
  db::MapStore maps_;
  db::RunStore runs_;
  db::TokenStore tokens_;
  db::SweepStore sweep_store_;
  std::chrono::steady_clock::time_point started_;
  api::StreamHub hub_;
  std::unique_ptr<Recorder> recorder_;
  std::unique_ptr<Robot> robot_;
  std::unique_ptr<Sweeps> sweeps_;
  std::unique_ptr<ControlLoop> loop_;
  api::RestApi rest_;
  boost::asio::io_context io_;
  api::HttpServer http_;
  std::vector<std::thread> io_threads_;

  std::string extra_admin_hash_;
  mutable std::mutex auth_mutex_;
  std::unordered_map<std::string, api::Role> role_cache_;  // token hash -> role
  std::mutex map_mutex_;  // serialises map activation and publication
};

}  // namespace mobot::server
