#include "server/robot.h"

#include <algorithm>

#include "api/api_error.h"
#include "core/control/velocity_limits.h"
#include "core/estimation/odometry_covariance.h"

namespace mobot::server {
namespace {

estimation::OdometryParams nominal_odometry(const sim::RobotProfile& profile) {
  // The nominal geometry: the simulator's systematic wheel errors stay uncorrected until the
  // UMBmark calibration measures them.
  return {profile.wheel_radius_m, profile.wheel_radius_m, profile.track_m,
          static_cast<int>(profile.ticks_per_wheel_rev)};
}

std::array<double, 9> to_array(const Eigen::Matrix3d& m) {
  std::array<double, 9> out{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out[static_cast<std::size_t>(r * 3 + c)] = m(r, c);
  }
  return out;
}

}  // namespace

Robot::Robot(const Config& config, sim::World world, api::StreamHub& hub, Recorder& recorder)
    : config_(config),
      hub_(hub),
      recorder_(recorder),
      period_s_(1.0 / config.robot.control_rate_hz),
      seed_(config.sim.seed),
      odometry_(nominal_odometry(sim::r1_profile())),
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
  odometry_ = estimation::WheelOdometry(nominal_odometry(sim_->profile()), pose);
  pose_ = pose;
  covariance_ = Eigen::Matrix3d::Zero();
}

void Robot::tick() {
  std::lock_guard lock(mutex_);
  sim_->step(period_s_);
  now_s_ += period_s_;
  ++ticks_;
  read_sensors();
  check_faults();
  drive();
  publish();
  hub_.flush();
}

void Robot::read_sensors() {
  const double t_s = now_s_;
  msgs::WheelEncoders encoders = sim_->read_encoders();
  encoders.stamp_s = t_s;
  update_odometry(encoders);
  watchdog_.seen("encoders", t_s);
  if (laser_schedule_.due(t_s)) {
    new_scan_ = sim_->read_laser();
    new_scan_->stamp_s = t_s;
    watchdog_.seen("laser", t_s);
    laser_schedule_.taken(t_s);
  }
  if (sonar_schedule_.due(t_s)) {
    new_sonar_ = sim_->read_sonar();
    new_sonar_->stamp_s = t_s;
    watchdog_.seen("sonar", t_s);
    sonar_schedule_.taken(t_s);
  }
  if (compass_schedule_.due(t_s)) {
    compass_ = sim_->read_compass();
    compass_->stamp_s = t_s;
    watchdog_.seen("compass", t_s);
    compass_schedule_.taken(t_s);
  }
}

void Robot::update_odometry(const msgs::WheelEncoders& encoders) {
  const geometry::Pose2D before = odometry_.odometry().pose;
  const msgs::Odometry& odom = odometry_.update(encoders);
  const estimation::WheelTravel& travel = odometry_.last_travel();
  covariance_ = estimation::propagate_odometry_covariance(
      covariance_, before, travel.left_m, travel.right_m, odometry_.params().track_m, {});
  pose_ = odom.pose;
}

void Robot::check_faults() {
  const double t_s = now_s_;
  for (const auto& collision : sim_->take_collisions()) {
    ++collisions_;
    // The base stops and stays stopped until somebody commands it again.
    drop_commands();
    record_event("collision", {{"with", collision.with},
                               {"x", collision.pose.x},
                               {"y", collision.pose.y}});
  }
  std::vector<std::string> stale = watchdog_.stale_required(t_s);
  if (stale != stale_sensors_) {
    for (const auto& name : stale) {
      if (std::find(stale_sensors_.begin(), stale_sensors_.end(), name) == stale_sensors_.end()) {
        record_event("fault", {{"sensor", name}, {"reason", "stale"}});
      }
    }
    stale_sensors_ = std::move(stale);
  }
  if (!stale_sensors_.empty()) mux_.submit("safety", {}, t_s);
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
  const msgs::Odometry& odom = odometry_.odometry();
  hub_.publish_pose(t_s, pose_, odom.twist, to_array(covariance_));
  hub_.publish_odom(odom);
  if (new_scan_) {
    hub_.publish_scan(*new_scan_, geometry::compose(pose_, new_scan_->sensor_in_base));
    new_scan_.reset();
  }
  if (new_sonar_) {
    hub_.publish_sonar(*new_sonar_, pose_);
    new_sonar_.reset();
  }
  hub_.publish_truth({t_s, sim_->true_pose(), sim_->collision_count()});
  if (status_schedule_.due(t_s)) {
    hub_.publish_status(snapshot_locked());
    status_schedule_.taken(t_s);
  }
  if (sample_schedule_.due(t_s)) {
    recorder_.record_pose(t_s, pose_.x, pose_.y, pose_.theta);
    recorder_.set_distance(distance_before_reset_m_ + odometry_.travelled_m());
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
  const msgs::Twist clamped = control::clamp_to_limits(command, config_.robot.limits);
  mux_.submit("teleop", clamped, now_s_, ttl_ms / 1000.0);
  last_teleop_ = clamped;
  return clamped;
}

bool Robot::set_estop(bool engaged) {
  std::lock_guard lock(mutex_);
  if (engaged != estop_) {
    estop_ = engaged;
    if (engaged) {
      drop_commands();
      sim_->set_command({});
    }
    record_event("estop", {{"engaged", engaged}});
    hub_.flush();
  }
  return estop_;
}

std::string Robot::mode() const {
  if (estop_) return "estop";
  if (mux_.is_active("teleop", now_s_)) return "teleop";
  return "idle";
}

api::RobotSnapshot Robot::snapshot() const {
  std::lock_guard lock(mutex_);
  return snapshot_locked();
}

api::RobotSnapshot Robot::snapshot_locked() const {
  api::RobotSnapshot snapshot;
  snapshot.t_s = now_s_;
  snapshot.mode = mode();
  snapshot.pose = pose_;
  snapshot.velocity = odometry_.odometry().twist;
  snapshot.localization_method = "odometry";
  snapshot.covariance = to_array(covariance_);
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
  distance_before_reset_m_ += odometry_.travelled_m();
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
  return distance_before_reset_m_ + odometry_.travelled_m();
}

std::string Robot::metrics_text() const {
  std::lock_guard lock(mutex_);
  std::string out;
  out += "# HELP mobot_robot_time_seconds Robot clock.\n# TYPE mobot_robot_time_seconds gauge\n";
  out += "mobot_robot_time_seconds " + std::to_string(now_s_) + "\n";
  out += "# HELP mobot_collisions_total Collisions since start.\n";
  out += "# TYPE mobot_collisions_total counter\n";
  out += "mobot_collisions_total " + std::to_string(collisions_) + "\n";
  out += "# HELP mobot_estop E-stop engaged (1) or not (0).\n# TYPE mobot_estop gauge\n";
  out += "mobot_estop " + std::to_string(estop_ ? 1 : 0) + "\n";
  out += "# HELP mobot_sensor_rate_hz Measured sensor rate.\n# TYPE mobot_sensor_rate_hz gauge\n";
  for (const auto& sensor : watchdog_.status(now_s_)) {
    out += "mobot_sensor_rate_hz{sensor=\"" + sensor.name + "\"} " +
           std::to_string(sensor.rate_hz) + "\n";
  }
  return out;
}

}  // namespace mobot::server
