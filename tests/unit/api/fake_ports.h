// Fake ports for the API's unit tests: a small robot whose answers the test controls. Requests
// that wait complete at once (inside the call, as a port may) or, with `defer`, when the test runs
// what was kept, from whichever thread it likes.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "api/ports/ports.h"

namespace mobot::api::test {

// How the fakes answer; shared by all of them.
class Answers {
 public:
  // Completions are kept for run_pending() instead of being called inside the port call.
  bool defer = false;
  // Every request is refused with this: through its Completion, or thrown by a method that
  // answers at once.
  std::optional<DomainError> refusal;
  // A misbehaving port: calls the Completion this many times, then (optionally) throws.
  int calls = 1;
  bool throw_after_completing = false;

  // `command`: the state change an accepted request makes, recorded (see accepted()).
  template <class T>
  void complete(Completion<T> done, Result<T> result, const char* command = nullptr) {
    if (refusal) result = Result<T>(*refusal);
    if (command != nullptr && result.ok()) record(command);
    if (!result.ok()) ++refusals;
    if (!defer) {
      call(done, result);
      return;
    }
    std::lock_guard lock(mutex_);
    pending_.push_back(
        [this, done = std::move(done), result = std::move(result)] { call(done, result); });
  }

  void check() const {
    if (!refusal) return;
    ++refusals;
    throw DomainException(*refusal);
  }

  // How many times a fake said no (a refusal of its own, or `refusal`): the request reached the
  // robot and the robot refused it.
  mutable std::atomic<int> refusals{0};

  // Runs the kept completions on the calling thread; returns how many ran.
  std::size_t run_pending() {
    std::vector<std::function<void()>> pending;
    {
      std::lock_guard lock(mutex_);
      pending.swap(pending_);
    }
    for (auto& run : pending) run();
    return pending.size();
  }

  std::size_t pending() const {
    std::lock_guard lock(mutex_);
    return pending_.size();
  }

  // The state changes the fakes accepted, in order. A refused request records nothing: a reply
  // in 4xx must leave this as it was (DESIGN: bad input never changes state).
  void record(std::string command) {
    std::lock_guard lock(mutex_);
    accepted_.push_back(std::move(command));
  }
  std::vector<std::string> accepted() const {
    std::lock_guard lock(mutex_);
    return accepted_;
  }

 private:
  template <class T>
  void call(const Completion<T>& done, const Result<T>& result) {
    for (int i = 0; i < calls; ++i) done(result);
    if (throw_after_completing) {
      throw DomainException(ErrorKind::kConflict, "late_failure", "failed after completing");
    }
  }

  mutable std::mutex mutex_;
  std::vector<std::function<void()>> pending_;
  std::vector<std::string> accepted_;
};

class FakeControl : public ControlPort {
 public:
  explicit FakeControl(Answers& answers) : answers_(answers) {}

  double clock_s = 12.5;
  std::vector<std::string> planners{"astar", "voronoi"};
  std::vector<std::string> controllers{"lyapunov"};

  RobotSnapshot snapshot() const override {
    RobotSnapshot snapshot;
    snapshot.t_s = clock_s;
    snapshot.mode = "idle";
    return snapshot;
  }
  double time_s() const override { return clock_s; }
  void teleop(const msgs::Twist& command, int, Completion<msgs::Twist> done) override {
    answers_.complete(std::move(done), Result<msgs::Twist>(command), "teleop");
  }
  void set_estop(bool engaged, Completion<bool> done) override {
    answers_.complete(std::move(done), Result<bool>(engaged), "set_estop");
  }
  void submit_goal(const GoalRequest& request, Completion<navigation::Goal> done) override {
    navigation::Goal goal;
    goal.id = 1;
    goal.status = navigation::GoalStatus::kActive;
    goal.target = request.target;
    goal.has_heading = request.has_heading;
    goal.planner = request.planner;
    goal.controller = request.controller;
    answers_.complete(std::move(done), Result<navigation::Goal>(goal), "submit_goal");
  }
  std::vector<navigation::Goal> list_goals() const override { return {}; }
  std::optional<navigation::Goal> find_goal(std::int64_t) const override { return std::nullopt; }
  void cancel_goal(std::int64_t, Completion<navigation::Goal> done) override {
    answers_.complete(std::move(done),
                      Result<navigation::Goal>(DomainError{ErrorKind::kNotFound, "unknown_goal",
                                                           "no goal with this id"}));
  }
  void set_localization_pose(const geometry::Pose2D&, const std::array<double, 9>&,
                             Completion<Done> done) override {
    answers_.complete(std::move(done), Result<Done>(Done{}), "set_localization_pose");
  }
  std::vector<std::string> planner_names() const override { return planners; }
  std::vector<std::string> controller_names() const override { return controllers; }

 private:
  Answers& answers_;
};

class FakeMaps : public MapCatalogPort {
 public:
  explicit FakeMaps(Answers& answers) : answers_(answers) {}

  std::vector<MapInfo> list_maps() const override { return {}; }
  std::optional<MapInfo> map_info(std::int64_t) const override { return std::nullopt; }
  std::optional<mapping::OccupancyGrid> map_grid(std::int64_t) const override {
    return std::nullopt;
  }
  std::int64_t import_map(const std::string&, const mapping::OccupancyGrid&) override {
    answers_.record("import_map");
    return 1;
  }
  void activate_map(std::int64_t id, Completion<MapInfo> done) override {
    MapInfo info;
    info.id = id;
    info.name = "lab";
    info.active = true;
    answers_.complete(std::move(done), Result<MapInfo>(info), "activate_map");
  }
  void delete_map(std::int64_t) override {
    answers_.check();
    answers_.record("delete_map");
  }

  // Map 1 exists; zones are kept as given (the fake does not judge polygons).
  std::vector<mapping::KeepoutZone> zones;
  std::optional<std::vector<mapping::KeepoutZone>> list_zones(std::int64_t map_id) const override {
    if (map_id != 1) return std::nullopt;
    return zones;
  }
  void add_zone(std::int64_t map_id, const std::string& name,
                const std::vector<geometry::Point2D>& polygon,
                Completion<std::int64_t> done) override {
    if (map_id != 1) {
      return answers_.complete(std::move(done), Result<std::int64_t>(DomainError{
                                                    ErrorKind::kNotFound, "unknown_map", "none"}));
    }
    zones.push_back({static_cast<std::int64_t>(zones.size()) + 1, name, polygon});
    answers_.complete(std::move(done), Result<std::int64_t>(zones.back().id), "add_zone");
  }
  void delete_zone(std::int64_t, std::int64_t, Completion<Done> done) override {
    answers_.complete(std::move(done), Result<Done>(Done{}), "delete_zone");
  }

 private:
  Answers& answers_;
};

class FakeMapping : public MappingPort {
 public:
  explicit FakeMapping(Answers& answers) : answers_(answers) {}

  MappingStatus status;
  std::optional<std::string> last_save_as;

  MappingStatus mapping_status() const override { return status; }
  void start_mapping(Completion<MappingStatus> done) override {
    status.mapping = true;
    answers_.complete(std::move(done), Result<MappingStatus>(status), "start_mapping");
  }
  void stop_mapping(std::optional<std::string> save_as, Completion<MappingStopped> done) override {
    last_save_as = save_as;
    MappingStopped stopped;
    if (save_as) stopped.map_id = 5;
    answers_.complete(std::move(done), Result<MappingStopped>(stopped), "stop_mapping");
  }

 private:
  Answers& answers_;
};

class FakeLocalization : public LocalizationPort {
 public:
  explicit FakeLocalization(Answers& answers) : answers_(answers) {}

  std::string method = "ekf";

  std::vector<std::string> localization_methods() const override {
    return {"ekf", "odometry", "particle_filter"};
  }
  void set_localization_method(const std::string& name, Completion<std::string> done) override {
    method = name;
    answers_.complete(std::move(done), Result<std::string>(name), "set_localization_method");
  }
  void localize_globally(Completion<std::string> done) override {
    answers_.complete(std::move(done), Result<std::string>(std::string("particle_filter")),
                      "localize_globally");
  }

 private:
  Answers& answers_;
};

class FakeRuns : public RunArchivePort {
 public:
  explicit FakeRuns(Answers& answers) : answers_(answers) {}

  std::vector<RunInfo> runs{{3, "run-3", 100.0, std::nullopt, 1.5, 1, 0, 0}};

  void list_runs(Completion<std::vector<RunInfo>> done) const override {
    answers_.complete(std::move(done), Result<std::vector<RunInfo>>(runs));
  }
  void run_trajectory(std::int64_t, Completion<std::vector<TrajectoryPoint>> done) const override {
    answers_.complete(std::move(done), Result<std::vector<TrajectoryPoint>>(
                                           std::vector<TrajectoryPoint>{{0.0, 1.0, 2.0, 0.5}}));
  }
  void run_events(std::int64_t, Completion<std::vector<RunEvent>> done) const override {
    answers_.complete(std::move(done), Result<std::vector<RunEvent>>(std::vector<RunEvent>{}));
  }

 private:
  Answers& answers_;
};

// The token is the role's name.
class FakeTokens : public TokenAdminPort {
 public:
  // Tokens "viewer", "operator", "admin" (ids 1, 2, 3), and "operator2" (id 4), another person.
  std::optional<Caller> authenticate(std::string_view token) override {
    if (token == "viewer") return Caller{1, Role::kViewer, "viewer"};
    if (token == "operator") return Caller{2, Role::kOperator, "operator"};
    if (token == "admin") return Caller{3, Role::kAdmin, "admin"};
    if (token == "operator2") return Caller{4, Role::kOperator, "operator2"};
    return std::nullopt;
  }
  int created = 0;  // tokens made
  CreatedToken create_token(Role, const std::string&, std::optional<std::int64_t>) override {
    ++created;
    return {1, "token", std::nullopt};
  }
  std::vector<TokenInfo> list_tokens() const override { return {}; }
  bool revoke_token(std::int64_t) override { return false; }
  bool is_active(std::int64_t token_id) override {
    std::lock_guard lock(mutex_);
    return !inactive.contains(token_id);
  }
  // The token with this id is revoked from now on.
  void deactivate(std::int64_t token_id) {
    std::lock_guard lock(mutex_);
    inactive.insert(token_id);
  }

 private:
  std::mutex mutex_;
  std::set<std::int64_t> inactive;
};

class FakeSweeps : public SweepsPort {
 public:
  explicit FakeSweeps(Answers& answers) : answers_(answers) {}

  void start_sweep(const SweepRequest& request, Completion<SweepInfo> done) override {
    SweepInfo info;
    info.id = 1;
    info.status = "running";
    info.period_s = request.period_s;
    info.step_deg = request.step_deg;
    answers_.complete(std::move(done), Result<SweepInfo>(info), "start_sweep");
  }
  std::vector<SweepInfo> list_sweeps() const override { return {}; }
  std::optional<SweepInfo> find_sweep(std::int64_t) const override { return std::nullopt; }
  perception::PointCloud sweep_cloud(std::int64_t) const override {
    answers_.check();
    return {};
  }
  mapping::OccupancyGrid sweep_obstacle_map(std::int64_t) const override {
    answers_.check();
    return {};
  }
  void delete_sweep(std::int64_t) override {
    answers_.check();
    answers_.record("delete_sweep");
  }

 private:
  Answers& answers_;
};

class FakeSystem : public SystemPort {
 public:
  std::string backend_name() const override { return "fake"; }
  double uptime_s() const override { return 1.0; }
  std::string metrics_text() const override { return ""; }
};

class FakeSim : public SimControlPort {
 public:
  explicit FakeSim(Answers& answers) : answers_(answers) {}

  std::vector<WorldInfo> list_worlds() const override { return {{"lab", "a test world"}}; }
  SimTruth sim_truth() const override { return {}; }
  void sim_reset(const SimResetRequest&, Completion<Done> done) override {
    answers_.complete(std::move(done), Result<Done>(Done{}), "sim_reset");
  }
  void set_time_scale(double) override { answers_.record("set_time_scale"); }
  void add_sim_obstacle(const SimObstacleRequest&, Completion<int> done) override {
    answers_.complete(std::move(done), Result<int>(7), "add_sim_obstacle");
  }
  void remove_sim_obstacle(int, Completion<Done> done) override {
    answers_.complete(std::move(done), Result<Done>(Done{}), "remove_sim_obstacle");
  }
  std::optional<geometry::Pose2D> kidnapped_to;
  void kidnap(const geometry::Pose2D& pose, Completion<Done> done) override {
    kidnapped_to = pose;
    answers_.complete(std::move(done), Result<Done>(Done{}), "kidnap");
  }
  void add_sim_target(const SimTargetRequest& request, Completion<int> done) override {
    last_target = request;
    answers_.complete(std::move(done), Result<int>(1), "add_sim_target");
  }
  void remove_sim_target(int id, Completion<Done> done) override {
    if (id != 1) {
      return answers_.complete(std::move(done),
                               Result<Done>(DomainError{ErrorKind::kNotFound, "unknown_target", "no"}));
    }
    answers_.complete(std::move(done), Result<Done>(Done{}), "remove_sim_target");
  }
  std::optional<SimTargetRequest> last_target;

 private:
  Answers& answers_;
};

// A robot without a camera: every camera request is refused with no_camera.
class FakeCamera : public CameraPort {
 public:
  mutable std::atomic<int> refusals{0};  // as Answers::refusals

  std::optional<CameraDescription> camera() const override { return std::nullopt; }
  std::shared_ptr<const msgs::Image> snapshot() const override { throw DomainException(refusal()); }
  void set_pan_tilt(double, double, Completion<CameraDescription::Head> done) override {
    done(refusal());
  }
  void start_tracking(const PixelBox&, Completion<TrackingSnapshot> done) override {
    done(refusal());
  }
  TrackingSnapshot tracking() const override { throw DomainException(refusal()); }
  void stop_tracking(Completion<TrackingSnapshot> done) override { done(refusal()); }
  void start_follow(double, Completion<Done> done) override { done(refusal()); }
  void stop_follow(Completion<Done> done) override { done(refusal()); }

 private:
  DomainError refusal() const {
    ++refusals;
    return {ErrorKind::kNotFound, "no_camera", "no camera"};
  }
};

// Keeps what it is asked to record, and completes at once.
class FakeAudit : public AuditPort {
 public:
  void record_command(CommandRecord record, Completion<Done> done) override {
    {
      std::lock_guard lock(mutex_);
      records_.push_back(std::move(record));
    }
    done(Done{});
  }
  std::vector<CommandRecord> records() const {
    std::lock_guard lock(mutex_);
    return records_;
  }

 private:
  mutable std::mutex mutex_;
  std::vector<CommandRecord> records_;
};

struct FakePorts {
  Answers answers;
  FakeControl control{answers};
  FakeMaps maps{answers};
  FakeMapping mapping{answers};
  FakeLocalization localization{answers};
  FakeRuns runs{answers};
  FakeTokens tokens;
  FakeSweeps sweeps{answers};
  FakeSystem system;
  FakeSim sim{answers};
  FakeCamera camera;
  FakeAudit audit;

  // The doors into this fake robot, with or without the simulator's.
  Ports ports(bool simulated = true) {
    return {control, maps,   mapping, localization, runs, tokens,
            sweeps,  system, camera,  audit,        simulated ? &sim : nullptr};
  }
};

}  // namespace mobot::api::test
