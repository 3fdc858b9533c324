#include "server/robot.h"

#include <algorithm>

#include "api/api_error.h"
#include "api/prometheus_text.h"
#include "core/control/velocity_limits.h"
#include "core/perception/map_line_extractor.h"

namespace mobot::server {
namespace {

// The profile's nominal geometry, unless the config holds calibrated values: the simulator's
// systematic wheel errors stay in the odometry until a UMBmark calibration measures them.
estimation::OdometryParams odometry_params(const OdometrySection& calibrated,
                                           const sim::RobotProfile& profile) {
  const auto or_nominal = [](double value, double nominal) { return value > 0.0 ? value : nominal; };
  return {or_nominal(calibrated.left_wheel_radius_m, profile.wheel_radius_m),
          or_nominal(calibrated.right_wheel_radius_m, profile.wheel_radius_m),
          or_nominal(calibrated.track_m, profile.track_m),
          static_cast<int>(profile.ticks_per_wheel_rev)};
}

std::array<double, 9> to_array(const Eigen::Matrix3d& m) {
  std::array<double, 9> out{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out[static_cast<std::size_t>(r * 3 + c)] = m(r, c);
  }
  return out;
}

std::string plan_error_message(planning::PlanError error) {
  switch (error) {
    case planning::PlanError::kGoalOutsideMap:
      return "the goal lies outside the active map";
    case planning::PlanError::kGoalInObstacle:
      return "the robot does not fit at the goal: it is in or too close to an obstacle";
    case planning::PlanError::kNoPath:
      return "no collision-free path leads from the robot to the goal";
    case planning::PlanError::kStartInObstacle:
      return "the robot is inside an obstacle and cannot get out";
    case planning::PlanError::kStartOutsideMap:
      return "the robot is outside the active map";
    case planning::PlanError::kInvalidPose:
      return "the goal is not a finite pose";
    case planning::PlanError::kNoMap:
      return "no map is active";
  }
  return "planning failed";
}

}  // namespace

Robot::Robot(const Config& config, sim::World world, api::StreamHub& hub, Recorder& recorder)
    : config_(config),
      hub_(hub),
      recorder_(recorder),
      period_s_(1.0 / config.robot.control_rate_hz),
      seed_(config.sim.seed),
      localization_(config.localization, odometry_params(config.odometry, sim::r1_profile()), world.start),
      navigation_(config),
      mux_(config.robot.mux_sources),
      smoother_(config.robot.limits),
      laser_schedule_(1.0 / config.robot.laser_rate_hz),
      sonar_schedule_(1.0 / config.robot.sonar_rate_hz),
      compass_schedule_(1.0 / config.robot.compass_rate_hz),
      status_schedule_(1.0),
      sample_schedule_(1.0 / config.recorder.trajectory_rate_hz) {
  const geometry::Pose2D start = world.start;
  sim_ = std::make_unique<sim::Simulator>(std::move(world), sim::r1_profile(), seed_);
  start_estimation(start);
  const double timeout_s = config.robot.sensor_timeout_s;
  watchdog_.add("encoders", timeout_s, true);
  watchdog_.add("laser", std::max(timeout_s, 2.5 / config.robot.laser_rate_hz), true);
  watchdog_.add("sonar", std::max(timeout_s, 2.5 / config.robot.sonar_rate_hz), false);
  watchdog_.add("compass", std::max(timeout_s, 2.5 / config.robot.compass_rate_hz), false);
}

void Robot::start_estimation(const geometry::Pose2D& pose) {
  // The simulator starts the robot here, give or take how well a robot is ever placed by hand
  // (1 cm, 1 degree): a zero covariance would claim a certainty no sensor has.
  localization_.reset(pose, Eigen::Matrix3d(Eigen::Vector3d(1e-4, 1e-4, 3e-4).asDiagonal()));
}

void Robot::tick() {
  std::lock_guard lock(mutex_);
  sim_->step(period_s_);
  now_s_ += period_s_;
  ++ticks_;
  read_sensors();
  scan_sweep();
  check_faults();
  navigate();
  drive();
  publish();
  hub_.flush();
}

void Robot::read_sensors() {
  const double t_s = now_s_;
  msgs::WheelEncoders encoders = sim_->read_encoders();
  encoders.stamp_s = t_s;
  localization_.on_encoders(encoders);
  watchdog_.seen("encoders", t_s);
  if (laser_schedule_.due(t_s)) {
    new_scan_ = sim_->read_laser();
    new_scan_->stamp_s = t_s;
    localization_.on_scan(*new_scan_);
    navigation_.observe_scan(*new_scan_,
                             geometry::compose(localization_.pose(), new_scan_->sensor_in_base),
                             localization_.pose(), t_s);
    watchdog_.seen("laser", t_s);
    laser_schedule_.taken(t_s);
  }
  if (sonar_schedule_.due(t_s)) {
    new_sonar_ = sim_->read_sonar();
    new_sonar_->stamp_s = t_s;
    navigation_.observe_sonar(*new_sonar_, localization_.pose());
    watchdog_.seen("sonar", t_s);
    sonar_schedule_.taken(t_s);
  }
  if (compass_schedule_.due(t_s)) {
    compass_ = sim_->read_compass();
    compass_->stamp_s = t_s;
    localization_.on_compass(*compass_);
    msgs::LandmarkBearings bearings = sim_->read_landmark_bearings();
    bearings.stamp_s = t_s;
    localization_.on_bearings(bearings);
    watchdog_.seen("compass", t_s);
    compass_schedule_.taken(t_s);
  }
}

void Robot::scan_sweep() {
  end_sweep(sweep_scanner_.tick(*sim_, localization_.pose(), now_s_, hub_));
}

void Robot::end_sweep(std::optional<SweepOutcome> outcome) {
  if (!outcome || !sweep_listener_) return;
  outcome->map_generation = map_generation_;
  sweep_listener_(std::move(*outcome));
}

void Robot::set_sweep_listener(std::function<void(SweepOutcome)> listener) {
  std::lock_guard lock(mutex_);
  sweep_listener_ = std::move(listener);
}

double Robot::start_sweep(std::int64_t id, const perception::SweepMode& mode) {
  std::lock_guard lock(mutex_);
  if (sweep_scanner_.running()) {
    throw api::ApiError(409, "sweep_running", "a 3D sweep is running: wait until it is done");
  }
  sweep_scanner_.start(id, mode, now_s_, sim_->profile(), seed_ + static_cast<std::uint64_t>(id));
  return now_s_;
}

std::optional<SweepProgress> Robot::sweep_progress() const {
  std::lock_guard lock(mutex_);
  return sweep_scanner_.progress();
}

geometry::Point2D Robot::obstacle_lattice() const {
  std::lock_guard lock(mutex_);
  return obstacle_layer_.lattice_origin();
}

std::optional<int> Robot::apply_3d_obstacles(const mapping::OccupancyGrid& observed,
                                             std::uint64_t map_generation) {
  std::shared_ptr<const mapping::OccupancyGrid> layer;
  std::uint64_t generation = 0;
  {
    std::lock_guard lock(mutex_);
    if (obstacle_layer_.empty() || map_generation != map_generation_) return std::nullopt;
    obstacle_layer_.apply(observed);
    layer = std::make_shared<const mapping::OccupancyGrid>(obstacle_layer_.grid());
    generation = map_generation_;
  }
  // Re-inflating the map with the layer takes a while: outside the mutex, like set_map.
  if (!navigation_.set_obstacle_layer(layer, generation)) return std::nullopt;
  return static_cast<int>(std::count(layer->cells().begin(), layer->cells().end(),
                                     mapping::OccupancyGrid::kOccupied));
}

void Robot::check_faults() {
  const double t_s = now_s_;
  for (const auto& collision : sim_->take_collisions()) {
    ++collisions_;
    // The base stops and stays stopped until somebody commands it again.
    drop_commands();
    navigation_.end_active(navigation::GoalStatus::kFailed, "collision", t_s);
    record_event("collision", {{"with", collision.with},
                               {"x", collision.pose.x},
                               {"y", collision.pose.y}});
  }
  std::vector<std::string> stale = watchdog_.stale_required(t_s);
  if (stale != stale_sensors_) {
    for (const auto& name : stale) {
      if (std::find(stale_sensors_.begin(), stale_sensors_.end(), name) == stale_sensors_.end()) {
        record_event("fault", {{"sensor", name}, {"reason", "stale"}});
        navigation_.end_active(navigation::GoalStatus::kFailed, "sensor_fault", t_s);
      }
    }
    stale_sensors_ = std::move(stale);
  }
  if (!stale_sensors_.empty()) mux_.submit("safety", {}, t_s);
}

void Robot::navigate() {
  const double t_s = now_s_;
  const auto command =
      navigation_.tick(t_s, localization_.pose(), localization_.odometry().twist);
  if (command) {
    mux_.submit("navigation", *command, t_s);
  } else if (navigation_was_active_) {
    // The goal ended: the last navigation command must not live on until its mux time-out.
    mux_.clear("navigation");
  }
  navigation_was_active_ = command.has_value();
  publish_goal_changes();
}

void Robot::publish_goal_changes() {
  for (const auto& goal : navigation_.take_changes()) {
    hub_.publish_goal(now_s_, goal);
    if (goal.status == navigation::GoalStatus::kActive) hub_.publish_path(now_s_, goal);
    nlohmann::json detail{{"id", goal.id},
                          {"status", navigation::to_string(goal.status)},
                          {"x", goal.target.x},
                          {"y", goal.target.y}};
    if (!goal.reason.empty()) detail["reason"] = goal.reason;
    if (goal.replans > 0) detail["replans"] = goal.replans;
    record_event("goal", detail);
  }
}

void Robot::drive() {
  const double t_s = now_s_;
  const bool teleop_active = mux_.is_active("teleop", t_s);
  if (teleop_was_active_ && !teleop_active &&
      (last_teleop_.linear_mps != 0.0 || last_teleop_.angular_radps != 0.0)) {
    record_event("teleop_timeout", {{"ttl_expired", true}});
    last_teleop_ = {};
  }
  teleop_was_active_ = teleop_active;

  if (estop_) {
    smoother_.halt();
  } else {
    smoother_.step(mux_.select(t_s).command, period_s_);
  }
  sim_->set_command(smoother_.current());
}

void Robot::publish() {
  const double t_s = now_s_;
  const msgs::Odometry& odom = localization_.odometry();
  const geometry::Pose2D& pose = localization_.pose();
  hub_.publish_pose(t_s, pose, odom.twist, to_array(localization_.covariance()));
  hub_.publish_odom(odom);
  if (new_scan_) {
    hub_.publish_scan(*new_scan_, geometry::compose(pose, new_scan_->sensor_in_base));
    new_scan_.reset();
  }
  if (new_sonar_) {
    hub_.publish_sonar(*new_sonar_, pose);
    new_sonar_.reset();
  }
  hub_.publish_truth({t_s, sim_->true_pose(), sim_->collision_count()});
  if (status_schedule_.due(t_s)) {
    hub_.publish_status(snapshot_locked());
    status_schedule_.taken(t_s);
  }
  if (sample_schedule_.due(t_s)) {
    recorder_.record_pose(t_s, pose.x, pose.y, pose.theta);
    recorder_.set_distance(distance_before_reset_m_ + localization_.travelled_m());
    sample_schedule_.taken(t_s);
  }
}

void Robot::record_event(const std::string& kind, const nlohmann::json& detail) {
  const double t_s = now_s_;
  recorder_.record_event(t_s, kind, detail.dump());
  hub_.publish_event(t_s, kind, detail);
}

msgs::Twist Robot::teleop(const msgs::Twist& command, int ttl_ms) {
  std::lock_guard lock(mutex_);
  if (estop_) throw api::ApiError(409, "estop_engaged", "e-stop is engaged: release it first");
  navigation_.end_active(navigation::GoalStatus::kCanceled, "teleop_override", now_s_);
  publish_goal_changes();
  const msgs::Twist clamped = control::clamp_to_limits(command, config_.robot.limits);
  mux_.submit("teleop", clamped, now_s_, ttl_ms / 1000.0);
  last_teleop_ = clamped;
  return clamped;
}

navigation::Goal Robot::submit_goal(const GoalRequest& request) {
  std::future<PlanningWorker::Outcome> planned;
  {
    std::lock_guard lock(mutex_);
    if (estop_) throw api::ApiError(409, "estop_engaged", "e-stop is engaged: release it first");
    planned = navigation_.plan(localization_.pose(), request);
  }
  // Planning takes milliseconds to tens of them: never under the mutex the control tick needs.
  const PlanningWorker::Outcome outcome = planned.get();
  if (outcome.error) {
    const std::string code(planning::error_code(*outcome.error));
    const int status = *outcome.error == planning::PlanError::kInvalidPose ? 400
                       : *outcome.error == planning::PlanError::kNoMap    ? 409
                                                                          : 422;
    throw api::ApiError(status, code, plan_error_message(*outcome.error));
  }
  std::lock_guard lock(mutex_);
  if (estop_) throw api::ApiError(409, "estop_engaged", "e-stop is engaged: release it first");
  const navigation::Goal goal = navigation_.start(request, outcome.path, now_s_);
  publish_goal_changes();
  return goal;
}

std::vector<navigation::Goal> Robot::goals() const {
  std::lock_guard lock(mutex_);
  return navigation_.list();
}

std::optional<navigation::Goal> Robot::goal(std::int64_t id) const {
  std::lock_guard lock(mutex_);
  return navigation_.find(id);
}

navigation::Goal Robot::cancel_goal(std::int64_t id) {
  std::lock_guard lock(mutex_);
  if (!navigation_.cancel(id, now_s_)) {
    throw api::ApiError(404, "unknown_goal", "no goal with this id");
  }
  publish_goal_changes();
  return *navigation_.find(id);
}

void Robot::set_localization_pose(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance) {
  std::lock_guard lock(mutex_);
  localization_.set_pose(pose, covariance);
  record_event("localization", {{"x", pose.x}, {"y", pose.y}, {"theta", pose.theta}});
}

void Robot::set_map(const mapping::OccupancyGrid& map) {
  // Inflating and extracting lines takes a while on a big map: outside the mutex.
  const std::uint64_t generation = navigation_.set_map(map);
  std::vector<perception::LineSegment> lines = perception::extract_map_lines(map);
  std::lock_guard lock(mutex_);
  // The 3D layer belongs to the map it was measured on, and so does a sweep's cloud.
  map_generation_ = generation;
  // IPaBD's cell (ALGORITHMS.md P2): a third of the robot's width.
  obstacle_layer_.reset(map, sim_->profile().footprint_width_m / 3.0);
  end_sweep(sweep_scanner_.abort("map_changed", now_s_));
  localization_.set_map_lines(std::move(lines));
  navigation_.end_active(navigation::GoalStatus::kCanceled, "map_changed", now_s_);
  publish_goal_changes();
}

bool Robot::set_estop(bool engaged) {
  std::lock_guard lock(mutex_);
  if (engaged != estop_) {
    estop_ = engaged;
    if (engaged) {
      drop_commands();
      sim_->set_command({});
      navigation_.end_active(navigation::GoalStatus::kCanceled, "estop", now_s_);
      publish_goal_changes();
    }
    record_event("estop", {{"engaged", engaged}});
    hub_.flush();
  }
  return estop_;
}

std::string Robot::mode() const {
  if (estop_) return "estop";
  if (mux_.is_active("teleop", now_s_)) return "teleop";
  if (navigation_.active()) return "navigating";
  return "idle";
}

double Robot::time_s() const {
  std::lock_guard lock(mutex_);
  return now_s_;
}

api::RobotSnapshot Robot::snapshot() const {
  std::lock_guard lock(mutex_);
  return snapshot_locked();
}

api::RobotSnapshot Robot::snapshot_locked() const {
  api::RobotSnapshot snapshot;
  snapshot.t_s = now_s_;
  snapshot.mode = mode();
  snapshot.pose = localization_.pose();
  snapshot.velocity = localization_.odometry().twist;
  snapshot.localization_method = localization_.method();
  snapshot.covariance = to_array(localization_.covariance());
  snapshot.kinematics = config_.robot.kinematics;
  snapshot.estop = estop_;
  for (const auto& sensor : watchdog_.status(snapshot.t_s)) {
    snapshot.sensors[sensor.name] = {sensor.ok, sensor.rate_hz};
  }
  return snapshot;
}

api::SimTruth Robot::truth() const {
  std::lock_guard lock(mutex_);
  return {now_s_, sim_->true_pose(), sim_->collision_count()};
}

void Robot::reset(std::optional<sim::World> world, std::optional<geometry::Pose2D> pose,
                  std::optional<std::uint64_t> seed) {
  std::lock_guard lock(mutex_);
  if (seed) seed_ = *seed;
  distance_before_reset_m_ += localization_.travelled_m();
  navigation_.end_active(navigation::GoalStatus::kCanceled, "reset", now_s_);
  publish_goal_changes();
  end_sweep(sweep_scanner_.abort("reset", now_s_));
  if (world) {
    const geometry::Pose2D start = pose.value_or(world->start);
    sim_ = std::make_unique<sim::Simulator>(std::move(*world), sim::r1_profile(), seed_);
    sim_->reset(start, seed_);
  } else {
    sim_->reset(pose.value_or(sim_->world().start), seed_);
  }
  start_estimation(sim_->true_pose());
  drop_commands();
  record_event("sim_reset", {{"world", sim_->world().name},
                             {"x", sim_->true_pose().x},
                             {"y", sim_->true_pose().y},
                             {"theta", sim_->true_pose().theta},
                             {"seed", seed_}});
}

bool Robot::pose_is_free(const geometry::Pose2D& pose) const {
  std::lock_guard lock(mutex_);
  return !sim_->pose_collides(pose);
}

int Robot::add_obstacle(double x_m, double y_m, double radius_m, double height_m) {
  std::lock_guard lock(mutex_);
  return sim_->add_obstacle(x_m, y_m, radius_m, height_m);
}

bool Robot::remove_obstacle(int id) {
  std::lock_guard lock(mutex_);
  return sim_->remove_obstacle(id);
}

void Robot::halt() {
  std::lock_guard lock(mutex_);
  drop_commands();
  sim_->set_command({});
}

void Robot::drop_commands() {
  mux_.clear_all();
  smoother_.halt();
  // A command dropped on purpose (e-stop, collision, reset) did not time out: no teleop_timeout.
  last_teleop_ = {};
  teleop_was_active_ = false;
}

std::string Robot::world_name() const {
  std::lock_guard lock(mutex_);
  return sim_->world().name;
}

double Robot::distance_m() const {
  std::lock_guard lock(mutex_);
  return distance_before_reset_m_ + localization_.travelled_m();
}

std::string Robot::metrics_text() const {
  std::lock_guard lock(mutex_);
  std::string out;
  api::append_metric(out, "mobot_robot_time_seconds", "gauge", "Robot clock.", now_s_);
  api::append_metric(out, "mobot_collisions_total", "counter", "Collisions since start.",
                     static_cast<double>(collisions_));
  api::append_metric(out, "mobot_estop", "gauge", "E-stop engaged (1) or not (0).",
                     estop_ ? 1.0 : 0.0);
  api::append_metric(out, "mobot_navigating", "gauge", "A goal is active (1) or not (0).",
                     navigation_.active() ? 1.0 : 0.0);
  out += localization_.metrics_text();
  bool first = true;
  for (const auto& sensor : watchdog_.status(now_s_)) {
    const std::string labels = "sensor=\"" + sensor.name + "\"";
    if (first) {
      api::append_metric(out, "mobot_sensor_rate_hz", "gauge", "Measured sensor rate.",
                         sensor.rate_hz, labels);
    } else {
      api::append_sample(out, "mobot_sensor_rate_hz", sensor.rate_hz, labels);
    }
    first = false;
  }
  return out;
}

}  // namespace mobot::server
