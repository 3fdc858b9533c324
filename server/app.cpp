#include "server/app.h"

#include <spdlog/spdlog.h>
#include <sys/stat.h>

#include <boost/asio/signal_set.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "api/api_error.h"
#include "api/prometheus_text.h"
#include "drivers/sim/world.h"
#include "server/token_auth.h"

namespace mobot::server {
namespace {

double unix_now_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::filesystem::path worlds_dir_of(const Config& config) {
  return config.sim.worlds_dir.empty() ? std::filesystem::path(MOBOT_DEFAULT_WORLDS_DIR)
                                       : config.sim.worlds_dir;
}

std::filesystem::path web_dir_of(const Config& config) {
  return config.server.web_dir.empty() ? std::filesystem::path(MOBOT_DEFAULT_WEB_DIR)
                                       : config.server.web_dir;
}

api::MapInfo to_api(const db::MapMeta& meta) {
  return {meta.id,           meta.name,   meta.width,          meta.height,
          meta.resolution_m, meta.origin, meta.created_unix_s, meta.active};
}

std::string default_run_name() {
  const std::time_t now = std::time(nullptr);
  char text[64];
  std::strftime(text, sizeof text, "run %Y-%m-%d %H:%M:%S", std::localtime(&now));
  return text;
}

api::StreamOptions stream_options(const Config& config) {
  api::StreamOptions options;
  options.max_frames_per_topic = static_cast<std::size_t>(config.stream.max_frames_per_topic);
  options.simulated = config.backend == "sim";
  auto rate = [&](api::TopicId topic) -> double& {
    return options.nominal_rate_hz[api::topic_index(topic)];
  };
  rate(api::TopicId::kPose) = config.robot.control_rate_hz;
  rate(api::TopicId::kOdom) = config.robot.control_rate_hz;
  rate(api::TopicId::kTruth) = config.robot.control_rate_hz;
  rate(api::TopicId::kScan) = config.robot.laser_rate_hz;
  rate(api::TopicId::kSonar) = config.robot.sonar_rate_hz;
  rate(api::TopicId::kStatus) = 1.0;
  return options;
}

db::Database open_database(const Config& config) {
  std::filesystem::create_directories(config.server.data_dir);
  return db::Database::open(config.server.data_dir / "mobot.sqlite");
}

}  // namespace

App::App(Config config)
    : config_(std::move(config)),
      worlds_dir_(worlds_dir_of(config_)),
      database_(open_database(config_)),
      maps_(database_),
      runs_(database_),
      tokens_(database_),
      sweep_store_(database_),
      started_(std::chrono::steady_clock::now()),
      hub_(stream_options(config_)),
      rest_(*this, hub_, {web_dir_of(config_), MOBOT_VERSION}),
      http_(io_, rest_, hub_, *this) {
  if (config_.backend != "sim") {
    throw ConfigError(
        "backend: 'hardware' needs the robot's drivers, and this build has none for the R1 "
        "profile yet; use --backend sim");
  }
  if (!config_.extra_admin_token.empty()) extra_admin_hash_ = hash_token(config_.extra_admin_token);
  ensure_admin_token();

  sim::World world = sim::load_world(sim::resolve_world(worlds_dir_, config_.sim.world));
  ensure_world_map(world.name, sim::surveyed_map(world, sim::r1_profile().height_m));

  runs_.close_dangling_runs(unix_now_s());
  const std::string run_name = config_.run_name.empty() ? default_run_name() : config_.run_name;
  const std::int64_t run_id = runs_.start_run(run_name, unix_now_s());
  recorder_ = std::make_unique<Recorder>(runs_, run_id, config_.recorder.flush_period_ms);
  robot_ = std::make_unique<Robot>(config_, std::move(world), hub_, *recorder_);
  sweeps_ = std::make_unique<Sweeps>(config_, sweep_store_, *robot_, *recorder_, hub_);
  loop_ = std::make_unique<ControlLoop>(robot_->period_s(), [this] { robot_->tick(); });
  publish_active_map();
}

App::~App() { shut_down(); }

void App::ensure_admin_token() {
  if (tokens_.count_admins() > 0) return;
  const std::string token = generate_token();
  tokens_.add(hash_token(token), db::Role::kAdmin, "first start", unix_now_s());
  const std::filesystem::path file = config_.server.data_dir / "admin.token";
  {
    std::ofstream out(file, std::ios::trunc);
    out << token << "\n";
  }
  ::chmod(file.c_str(), S_IRUSR | S_IWUSR);
  spdlog::info("created the admin token in {}", file.string());
}

void App::ensure_world_map(const std::string& world_name, const mapping::OccupancyGrid& floor) {
  std::lock_guard lock(map_mutex_);
  for (const auto& meta : maps_.list()) {
    if (meta.name == world_name) {
      if (!meta.active) maps_.activate(meta.id);
      return;
    }
  }
  const std::int64_t id = maps_.insert(world_name, floor, unix_now_s());
  maps_.activate(id);
}

void App::publish_active_map() {
  std::lock_guard lock(map_mutex_);
  const auto id = maps_.active_id();
  if (!id) return;
  auto grid = maps_.grid(*id);
  if (!grid) return;
  if (robot_) robot_->set_map(*grid);
  hub_.publish_map(robot_ ? robot_->time_s() : 0.0,
                   std::make_shared<const mapping::OccupancyGrid>(std::move(*grid)), *id);
  hub_.flush();
}

int App::run() {
  // Installed before the ready line: a SIGTERM right after it must stop the server cleanly, not
  // kill it with the default disposition.
  boost::asio::io_context signals_io;
  boost::asio::signal_set signals(signals_io, SIGINT, SIGTERM);
  int received = 0;
  signals.async_wait([&](boost::system::error_code, int signal) { received = signal; });

  const auto endpoint = http_.listen({config_.server.bind_address, config_.server.port});
  loop_->start(config_.sim.time_scale);
  const unsigned threads = std::max(2U, std::thread::hardware_concurrency());
  for (unsigned i = 0; i < threads; ++i) io_threads_.emplace_back([this] { io_.run(); });

  const std::string url =
      "http://" + endpoint.address().to_string() + ":" + std::to_string(endpoint.port());
  std::cout << "mobotd listening on " << url << std::endl;
  std::ifstream token_file(config_.server.data_dir / "admin.token");
  std::string admin_token;
  if (token_file >> admin_token) {
    std::cout << "dashboard: " << url << "/?token=" << admin_token << std::endl;
  }

  signals_io.run();
  spdlog::info("signal {} received: stopping the robot and closing the run", received);
  shut_down();
  return 0;
}

void App::shut_down() {
  if (!loop_) return;
  loop_->stop();
  robot_->halt();
  http_.stop();
  sweeps_->stop();  // records its last event: before the recorder stops
  hub_.close_all();
  recorder_->stop(unix_now_s());
  // Give sessions a moment to send their close frames, then stop the network threads.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  io_.stop();
  for (auto& thread : io_threads_) thread.join();
  io_threads_.clear();
  loop_.reset();
}

std::optional<api::Role> App::authenticate(std::string_view token) {
  if (token.size() > 256) return std::nullopt;
  const std::string hash = hash_token(token);
  if (!extra_admin_hash_.empty() && hash == extra_admin_hash_) return api::Role::kAdmin;
  {
    std::lock_guard lock(auth_mutex_);
    if (auto it = role_cache_.find(hash); it != role_cache_.end()) return it->second;
  }
  const auto role = tokens_.find_role(hash);
  if (!role) return std::nullopt;
  const auto api_role = static_cast<api::Role>(static_cast<int>(*role));
  std::lock_guard lock(auth_mutex_);
  role_cache_[hash] = api_role;
  return api_role;
}

double App::uptime_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
}

msgs::Twist App::teleop(const msgs::Twist& command, int ttl_ms) {
  return robot_->teleop(command, ttl_ms);
}

bool App::set_estop(bool engaged) {
  const bool estop = robot_->set_estop(engaged);
  // The robot is already stopped; the reply waits until the e-stop event is on disk, so an
  // acknowledged e-stop is in the run even if the server is killed right after.
  recorder_->flush();
  return estop;
}

navigation::Goal App::submit_goal(const api::GoalRequest& request) {
  navigation::Goal goal = robot_->submit_goal(request);
  // The goal events (a preempted goal, this one starting) are in the run before the reply.
  recorder_->flush();
  return goal;
}

navigation::Goal App::cancel_goal(std::int64_t id) {
  navigation::Goal goal = robot_->cancel_goal(id);
  recorder_->flush();
  return goal;
}

void App::set_localization_pose(const geometry::Pose2D& pose,
                                const std::array<double, 9>& covariance) {
  Eigen::Matrix3d cov;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) cov(r, c) = covariance[static_cast<std::size_t>(r * 3 + c)];
  }
  robot_->set_localization_pose(pose, cov);
  recorder_->flush();
}

std::vector<api::MapInfo> App::list_maps() const {
  std::vector<api::MapInfo> out;
  for (const auto& meta : maps_.list()) out.push_back(to_api(meta));
  return out;
}

std::optional<api::MapInfo> App::map_info(std::int64_t id) const {
  const auto meta = maps_.meta(id);
  if (!meta) return std::nullopt;
  return to_api(*meta);
}

std::optional<mapping::OccupancyGrid> App::map_grid(std::int64_t id) const {
  return maps_.grid(id);
}

std::int64_t App::import_map(const std::string& name, const mapping::OccupancyGrid& grid) {
  return maps_.insert(name, grid, unix_now_s());
}

void App::activate_map(std::int64_t id) {
  {
    std::lock_guard lock(map_mutex_);
    if (!maps_.activate(id)) throw api::ApiError(404, "unknown_map", "no map with this id");
  }
  publish_active_map();
}

void App::delete_map(std::int64_t id) {
  std::lock_guard lock(map_mutex_);
  switch (maps_.remove(id)) {
    case db::MapStore::RemoveResult::kRemoved:
      return;
    case db::MapStore::RemoveResult::kNotFound:
      throw api::ApiError(404, "unknown_map", "no map with this id");
    case db::MapStore::RemoveResult::kActive:
      throw api::ApiError(409, "map_active", "the active map cannot be deleted: activate another");
  }
}

std::vector<api::RunInfo> App::list_runs() const {
  // The current run's goal counts come from its events: the ones still buffered count too.
  recorder_->flush();
  std::vector<api::RunInfo> out;
  for (const auto& run : runs_.list()) {
    out.push_back({run.id, run.name, run.started_unix_s, run.ended_unix_s, run.distance_m,
                   run.goals.succeeded, run.goals.failed, run.goals.canceled});
  }
  // The current run's distance is live, not as of the last flush.
  for (auto& run : out) {
    if (run.id == recorder_->run_id()) run.distance_m = robot_->distance_m();
  }
  return out;
}

std::optional<std::vector<api::TrajectoryPoint>> App::run_trajectory(std::int64_t id) const {
  if (!runs_.get(id)) return std::nullopt;
  if (id == recorder_->run_id()) recorder_->flush();
  std::vector<api::TrajectoryPoint> out;
  for (const auto& sample : runs_.trajectory(id)) {
    out.push_back({sample.t_s, sample.x, sample.y, sample.theta});
  }
  return out;
}

std::optional<std::vector<api::RunEvent>> App::run_events(std::int64_t id) const {
  if (!runs_.get(id)) return std::nullopt;
  if (id == recorder_->run_id()) recorder_->flush();
  std::vector<api::RunEvent> out;
  for (const auto& event : runs_.events(id)) out.push_back({event.t_s, event.kind, event.detail_json});
  return out;
}

std::pair<std::int64_t, std::string> App::create_token(api::Role role, const std::string& label) {
  const std::string token = generate_token();
  const auto id = tokens_.add(hash_token(token), static_cast<db::Role>(static_cast<int>(role)),
                              label, unix_now_s());
  return {id, token};
}

std::vector<api::TokenInfo> App::list_tokens() const {
  std::vector<api::TokenInfo> out;
  for (const auto& token : tokens_.list()) {
    out.push_back({token.id, static_cast<api::Role>(static_cast<int>(token.role)), token.label,
                   token.created_unix_s, token.revoked});
  }
  return out;
}

bool App::revoke_token(std::int64_t id) {
  if (!tokens_.revoke(id)) return false;
  // A revoked token must stop working at once, not when its cache entry ages out.
  std::lock_guard lock(auth_mutex_);
  role_cache_.clear();
  return true;
}

std::vector<api::WorldInfo> App::list_worlds() const {
  std::vector<api::WorldInfo> out;
  for (const auto& world : sim::list_worlds(worlds_dir_)) out.push_back({world.name, world.description});
  return out;
}

void App::sim_reset(const api::SimResetRequest& request) {
  std::optional<sim::World> world;
  if (request.world) {
    try {
      world = sim::load_world(sim::resolve_world(worlds_dir_, *request.world));
    } catch (const sim::WorldError& error) {
      throw api::ApiError(400, "unknown_world", error.what());
    }
  }
  if (request.pose) {
    const bool free = world ? !sim::Simulator(*world, sim::r1_profile(), 0).pose_collides(*request.pose)
                            : robot_->pose_is_free(*request.pose);
    if (!free) throw api::ApiError(400, "pose_in_obstacle", "the robot does not fit at that pose");
  }
  if (world) ensure_world_map(world->name, sim::surveyed_map(*world, sim::r1_profile().height_m));
  robot_->reset(std::move(world), request.pose, request.seed);
  recorder_->flush();
  if (request.world) publish_active_map();
}

void App::set_time_scale(double time_scale) { loop_->set_time_scale(time_scale); }

int App::add_sim_obstacle(double x_m, double y_m, double radius_m, double height_m) {
  return robot_->add_obstacle(x_m, y_m, radius_m, height_m);
}

bool App::remove_sim_obstacle(int id) { return robot_->remove_obstacle(id); }

std::string App::metrics_text() const {
  std::string out = robot_->metrics_text() + loop_->metrics_text() + recorder_->metrics_text();
  api::append_metric(out, "mobot_uptime_seconds", "gauge", "Seconds since start.", uptime_s());
  return out;
}

}  // namespace mobot::server
