#include "drivers/sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/kinematics/diff_drive.h"
#include "drivers/sim/tilted_fan.h"
#include "drivers/sim/world_slice.h"

namespace mobot::sim {
namespace {

// A substep moves no point of the body further than this, so it cannot jump through a one-cell
// wall and a collision is found close to where it happens.
constexpr double kMaxSubstepTravel_m = 0.02;
// Bisections that place a colliding robot against the obstacle: 0.02 m / 2^10 = 0.02 mm.
constexpr int kContactBisections = 10;
constexpr int kSonarRaysPerCone = 7;
// A Sharp ranger's spot is a few centimetres across: three rays span its beam.
constexpr int kIrRaysPerBeam = 3;
constexpr double kNoReturnBeyondMax_m = 1.0;
// The bearing landmarks are lit cylinders 10 cm across (R1): a sight line that reaches the
// cylinder's surface sees it.
constexpr double kLandmarkRadius_m = 0.05;

// New streams go at the end: the existing ones keep their seeds.
enum class Stream : std::uint32_t {
  kDrive = 1,
  kLaser,
  kSonar,
  kCompass,
  kCamera,
  kTilt,
  kSlip,
  kIr,
  kHeadRange
};

std::mt19937_64 random_stream(std::uint64_t seed, Stream stream) {
  std::seed_seq sequence{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                         static_cast<std::uint32_t>(stream)};
  return std::mt19937_64(sequence);
}

double gaussian(std::mt19937_64& rng, double sigma) {
  if (sigma <= 0.0) return 0.0;
  return std::normal_distribution<double>(0.0, sigma)(rng);
}

RobotProfile validated(RobotProfile p) {
  const auto positive = [](double value) { return std::isfinite(value) && value > 0.0; };
  if (!positive(p.wheel_radius_m) || !positive(p.track_m) || p.ticks_per_wheel_rev <= 0 ||
      !positive(p.footprint_length_m) || !positive(p.footprint_width_m) || !positive(p.height_m) ||
      !positive(p.laser_step_rad) || !positive(p.laser_fov_rad) || !positive(p.laser_range_max_m) ||
      !positive(p.sonar_range_max_m) || !positive(p.left_wheel_scale) ||
      !positive(p.right_wheel_scale) || !positive(p.track_scale) || !positive(p.max_linear_mps) ||
      !positive(p.max_angular_radps)) {
    throw std::invalid_argument("robot profile: geometry, ranges, scales and limits must be > 0");
  }
  if (!std::isfinite(p.camera_range_m) || p.camera_range_m < 0.0 ||
      !std::isfinite(p.bearing_sigma_rad) || p.bearing_sigma_rad < 0.0) {
    throw std::invalid_argument("robot profile: camera range and bearing sigma must be >= 0");
  }
  const auto non_negative = [](double value) { return std::isfinite(value) && value >= 0.0; };
  if (!non_negative(p.sonar_height_m) || !non_negative(p.laser_range_sigma_fraction) ||
      !non_negative(p.slip_noise_fraction) || !positive(p.slip_noise_correlation_s) ||
      !non_negative(p.traction_accel_mps2)) {
    throw std::invalid_argument(
        "robot profile: sonar height, range sigma fraction, slip noise and traction must be >= 0 "
        "and the slip correlation time > 0");
  }
  if (!p.ir_sensors_in_base.empty() &&
      (!positive(p.ir_height_m) || !non_negative(p.ir_cone_rad) || !positive(p.ir_rate_hz))) {
    throw std::invalid_argument(
        "robot profile: an IR ring needs a height and a rate > 0 and a beam width >= 0");
  }
  return p;
}

std::shared_ptr<const RayCaster> plane_at(const World& world, double z_m) {
  return std::make_shared<const RayCaster>(slice_at_height(world, z_m));
}

// A sensor at the height of one already sliced shares that slice.
std::shared_ptr<const RayCaster> plane_at(const World& world, double z_m,
                                          const std::shared_ptr<const RayCaster>& same_as,
                                          double same_as_z_m) {
  return z_m == same_as_z_m ? same_as : plane_at(world, z_m);
}

WheelSlipOptions slip_options(const RobotProfile& p) {
  return {p.slip_noise_fraction, p.slip_noise_correlation_s, p.traction_accel_mps2};
}

// The ring's sensor model before reset() draws each unit's gain.
SharpIrAdc unseeded_ir_adc(const RobotProfile& p) {
  std::mt19937_64 unused;
  return SharpIrAdc(p.ir_adc, 0, unused);
}

int laser_beams(const RobotProfile& p) {
  const int steps = static_cast<int>(std::lround(p.laser_fov_rad / p.laser_step_rad));
  const bool full_circle = p.laser_fov_rad >= 2.0 * std::numbers::pi - p.laser_step_rad / 2.0;
  return full_circle ? steps : steps + 1;
}

msgs::Twist clamp_command(const msgs::Twist& command, const RobotProfile& profile) {
  if (!std::isfinite(command.linear_mps) || !std::isfinite(command.angular_radps)) return {};
  return {std::clamp(command.linear_mps, -profile.max_linear_mps, profile.max_linear_mps),
          std::clamp(command.angular_radps, -profile.max_angular_radps, profile.max_angular_radps)};
}

}  // namespace

Simulator::Simulator(World world, RobotProfile profile, std::uint64_t seed)
    : world_(std::move(world)),
      profile_(validated(std::move(profile))),
      laser_plane_(plane_at(world_, profile_.laser_height_m)),
      sonar_plane_(
          plane_at(world_, profile_.sonar_height_m, laser_plane_, profile_.laser_height_m)),
      ir_plane_(
          profile_.ir_sensors_in_base.empty()
              ? nullptr
              : plane_at(world_, profile_.ir_height_m, sonar_plane_, profile_.sonar_height_m)),
      walls_(world_.floor),
      head_plane_(profile_.pan_tilt_camera
                      ? plane_at(world_, profile_.pan_tilt_camera->head.l0_m +
                                             profile_.pan_tilt_camera->head.l1_m)
                      : nullptr),
      body_(world_, profile_.footprint_length_m, profile_.footprint_width_m, profile_.height_m,
            profile_.footprint_offset_m),
      slip_(slip_options(profile_)),
      ir_adc_(unseeded_ir_adc(profile_)) {
  reset(world_.start, seed);
}

void Simulator::reset(const geometry::Pose2D& pose, std::uint64_t seed) {
  pose_ = {pose.x, pose.y, geometry::wrap_angle(pose.theta)};
  time_s_ = 0.0;
  command_ = {};
  steered_command_ = {};
  steering_rad_ = 0.0;
  wheel_angles_ = {};
  collisions_.clear();
  collision_count_ = 0;
  in_contact_ = false;
  obstacles_.clear();
  next_obstacle_id_ = 1;
  targets_.clear();
  next_target_id_ = 1;
  drive_rng_ = random_stream(seed, Stream::kDrive);
  laser_rng_ = random_stream(seed, Stream::kLaser);
  sonar_rng_ = random_stream(seed, Stream::kSonar);
  compass_rng_ = random_stream(seed, Stream::kCompass);
  camera_rng_ = random_stream(seed, Stream::kCamera);
  tilt_rng_ = random_stream(seed, Stream::kTilt);
  slip_rng_ = random_stream(seed, Stream::kSlip);
  ir_rng_ = random_stream(seed, Stream::kIr);
  head_range_rng_ = random_stream(seed, Stream::kHeadRange);
  // Start the PID error in its stationary distribution.
  left_speed_error_ = gaussian(drive_rng_, profile_.wheel_speed_noise_fraction);
  right_speed_error_ = gaussian(drive_rng_, profile_.wheel_speed_noise_fraction);
  slip_.reset(slip_rng_);
  // Each IR unit's own gain error, fixed for the run.
  ir_adc_ = SharpIrAdc(profile_.ir_adc, profile_.ir_sensors_in_base.size(), ir_rng_);
}

void Simulator::set_command(const msgs::Twist& command) {
  if (!profile_.steering) {
    command_ = clamp_command(command, profile_);
    return;
  }
  const kinematics::TricycleGeometry geometry{profile_.steering->type,
                                              profile_.steering->wheelbase_m};
  const kinematics::TricycleInput input =
      kinematics::tricycle_input_for(geometry, clamp_command(command, profile_));
  set_steered_command(input);
}

void Simulator::set_steered_command(const kinematics::TricycleInput& input) {
  if (!profile_.steering) throw std::logic_error("a differential base has no steering");
  if (!std::isfinite(input.drive_mps) || !std::isfinite(input.steer_rad)) {
    steered_command_ = {};
    return;
  }
  const double max_steer_rad = profile_.steering->max_steer_rad;
  steered_command_ = {std::clamp(input.drive_mps, -profile_.max_linear_mps, profile_.max_linear_mps),
                      std::clamp(input.steer_rad, -max_steer_rad, max_steer_rad)};
}

msgs::Twist Simulator::command() const {
  if (!profile_.steering) return command_;
  return kinematics::tricycle_body_velocity({profile_.steering->type, profile_.steering->wheelbase_m},
                                            {steered_command_.drive_mps, steering_rad_});
}

msgs::Twist Simulator::drive_twist(double dt_s) {
  if (!profile_.steering) return command_;
  const SteeringProfile& steering = *profile_.steering;
  // The servo holds the angle it is told plus its zero error, within the mechanical stop.
  const double target_rad = std::clamp(steered_command_.steer_rad + steering.steer_bias_rad,
                                       -steering.max_steer_rad, steering.max_steer_rad);
  const double max_change_rad = steering.steer_rate_radps * dt_s;
  steering_rad_ += std::clamp(target_rad - steering_rad_, -max_change_rad, max_change_rad);
  // The drive controller holds the turn rate within the base's limit for the angle the wheel is
  // really at (a steering still turning toward a tighter command would otherwise overshoot it).
  const kinematics::TricycleGeometry geometry{steering.type, steering.wheelbase_m};
  kinematics::TricycleInput drive{steered_command_.drive_mps, steering_rad_};
  const double turn_per_drive =
      std::abs(kinematics::tricycle_body_velocity(geometry, {1.0, steering_rad_}).angular_radps);
  if (turn_per_drive * std::abs(drive.drive_mps) > profile_.max_angular_radps) {
    drive.drive_mps = std::copysign(profile_.max_angular_radps / turn_per_drive, drive.drive_mps);
  }
  return kinematics::tricycle_body_velocity(geometry, drive);
}

void Simulator::step(double dt_s) {
  if (!std::isfinite(dt_s) || dt_s < 0.0) {
    throw std::invalid_argument("simulator step needs a finite dt_s >= 0");
  }
  if (dt_s == 0.0) return;
  update_wheel_noise(dt_s);
  // The motor controllers turn each wheel at the speed the nominal geometry asks for, give or take
  // the PID error; the true radii then decide how far the robot rolls. A steered base's rear
  // wheels turn as its steering makes the body move, with the same errors.
  const kinematics::WheelSpeeds wheel_mps =
      kinematics::wheels_from_twist(drive_twist(dt_s), profile_.track_m);
  // A steered base has one drive motor: its speed error moves both rear wheels alike (their
  // difference is the steering's).
  const double right_error = profile_.steering ? left_speed_error_ : right_speed_error_;
  const WheelAngles rotation{
      wheel_mps.left_mps / profile_.wheel_radius_m * (1.0 + left_speed_error_) * dt_s,
      wheel_mps.right_mps / profile_.wheel_radius_m * (1.0 + right_error) * dt_s};
  // The floor: what the wheels turn is what the encoders count, what they roll moves the base.
  WheelAngles ground = rotation;
  if (slip_.enabled()) {
    const double radius_m = profile_.wheel_radius_m;
    const WheelSlip::Travel travel = slip_.step(
        rotation.left_rad * radius_m / dt_s, rotation.right_rad * radius_m / dt_s, dt_s, slip_rng_);
    ground = {travel.left_m / radius_m, travel.right_m / radius_m};
  }

  const double half_diagonal_m =
      std::hypot(profile_.footprint_length_m / 2.0 + std::abs(profile_.footprint_offset_m),
                 profile_.footprint_width_m / 2.0);
  const geometry::Pose2D full = pose_after(pose_, ground, 1.0);
  const double travel_m =
      std::hypot(full.x - pose_.x, full.y - pose_.y) +
      std::abs(geometry::wrap_angle(full.theta - pose_.theta)) * half_diagonal_m;
  const int substeps = std::max(1, static_cast<int>(std::ceil(travel_m / kMaxSubstepTravel_m)));
  const WheelAngles slice{rotation.left_rad / substeps, rotation.right_rad / substeps};
  const WheelAngles ground_slice{ground.left_rad / substeps, ground.right_rad / substeps};
  for (int i = 0; i < substeps; ++i) {
    if (!drive_substep(slice, ground_slice)) break;
  }
  time_s_ += dt_s;
}

void Simulator::update_wheel_noise(double dt_s) {
  // First-order Gauss-Markov: the PID error wanders with a correlation time instead of changing
  // every step, so its effect on the path does not depend on the step length.
  const double sigma = profile_.wheel_speed_noise_fraction;
  const double tau_s = profile_.wheel_speed_noise_correlation_s;
  const double keep = tau_s > 0.0 ? std::exp(-dt_s / tau_s) : 0.0;
  const double innovation_sigma = sigma * std::sqrt(1.0 - keep * keep);
  left_speed_error_ = keep * left_speed_error_ + gaussian(drive_rng_, innovation_sigma);
  right_speed_error_ = keep * right_speed_error_ + gaussian(drive_rng_, innovation_sigma);
}

geometry::Pose2D Simulator::pose_after(const geometry::Pose2D& start, const WheelAngles& ground,
                                       double fraction) const {
  const double left_travel_m =
      ground.left_rad * fraction * profile_.wheel_radius_m * profile_.left_wheel_scale;
  const double right_travel_m =
      ground.right_rad * fraction * profile_.wheel_radius_m * profile_.right_wheel_scale;
  return kinematics::integrate_wheel_travel(start, left_travel_m, right_travel_m,
                                            profile_.track_m * profile_.track_scale);
}

bool Simulator::drive_substep(const WheelAngles& rotation, const WheelAngles& ground) {
  const geometry::Pose2D start = pose_;
  const geometry::Pose2D candidate = pose_after(start, ground, 1.0);
  const std::optional<std::string> hit = contact(candidate);
  // A robot already overlapping something (an obstacle dropped onto it) may drive out of it.
  if (!hit || contact(start)) {
    const bool moved = ground.left_rad != 0.0 || ground.right_rad != 0.0;
    if (moved && !hit) in_contact_ = false;
    pose_ = candidate;
    wheel_angles_.left_rad += rotation.left_rad;
    wheel_angles_.right_rad += rotation.right_rad;
    return true;
  }
  // Stop against the obstacle: the largest fraction of the substep that stays free.
  double free_fraction = 0.0;
  double blocked_fraction = 1.0;
  for (int i = 0; i < kContactBisections; ++i) {
    const double middle = (free_fraction + blocked_fraction) / 2.0;
    if (contact(pose_after(start, ground, middle))) {
      blocked_fraction = middle;
    } else {
      free_fraction = middle;
    }
  }
  pose_ = pose_after(start, ground, free_fraction);
  wheel_angles_.left_rad += rotation.left_rad * free_fraction;
  wheel_angles_.right_rad += rotation.right_rad * free_fraction;
  slip_.stop();
  record_collision(*hit);
  return false;
}

void Simulator::record_collision(const std::string& with) {
  command_ = {};
  steered_command_ = {};
  if (!in_contact_) {
    collisions_.push_back({with, pose_});
    ++collision_count_;
  }
  in_contact_ = true;
}

std::vector<Collision> Simulator::take_collisions() {
  std::vector<Collision> taken;
  taken.swap(collisions_);
  return taken;
}

std::optional<std::string> Simulator::contact(const geometry::Pose2D& pose) const {
  const OrientedRect footprint = body_.footprint_at(pose);
  for (const Obstacle& obstacle : obstacles_) {
    if (overlaps_circle(footprint, {obstacle.x_m, obstacle.y_m}, obstacle.radius_m)) {
      return "obstacle " + std::to_string(obstacle.id);
    }
  }
  return body_.contact(pose);
}

bool Simulator::pose_collides(const geometry::Pose2D& pose) const {
  return contact(pose).has_value();
}

msgs::WheelEncoders Simulator::read_encoders() {
  const double ticks_per_rad =
      static_cast<double>(profile_.ticks_per_wheel_rev) / (2.0 * std::numbers::pi);
  return {time_s_, static_cast<std::int64_t>(std::floor(wheel_angles_.left_rad * ticks_per_rad)),
          static_cast<std::int64_t>(std::floor(wheel_angles_.right_rad * ticks_per_rad))};
}

std::optional<double> Simulator::nearest_in_plane(geometry::Point2D from, double angle_rad,
                                                  double max_range_m) const {
  return nearest_at(*laser_plane_, profile_.laser_height_m, from, angle_rad, max_range_m);
}

std::optional<double> Simulator::nearest_at(const RayCaster& plane, double height_m,
                                            geometry::Point2D from, double angle_rad,
                                            double max_range_m) const {
  std::optional<double> nearest = plane.cast(from, angle_rad, max_range_m);
  for (const Obstacle& obstacle : obstacles_) {
    if (obstacle.height_m < height_m) continue;
    const std::optional<double> hit =
        cast_to_circle(from, angle_rad, {obstacle.x_m, obstacle.y_m}, obstacle.radius_m);
    if (hit && *hit <= max_range_m && (!nearest || *hit < *nearest)) nearest = hit;
  }
  return nearest;
}

void Simulator::add_obstacles_to_fan(geometry::Point2D from, double first_angle_rad,
                                     double increment_rad, std::span<double> ranges_m) const {
  const int beams = static_cast<int>(ranges_m.size());
  for (const Obstacle& obstacle : obstacles_) {
    if (obstacle.height_m < profile_.laser_height_m) continue;
    const double dx_m = obstacle.x_m - from.x;
    const double dy_m = obstacle.y_m - from.y;
    const double distance_m = std::hypot(dx_m, dy_m);
    if (distance_m <= obstacle.radius_m) {
      std::fill(ranges_m.begin(), ranges_m.end(), 0.0);  // the sensor is inside the obstacle
      return;
    }
    // Only the beams within the obstacle's angular half-width can hit it. Its bearing is taken
    // relative to the first beam, also one turn either way, so a full-circle scan's seam is
    // covered.
    const double half_width_rad = std::asin(obstacle.radius_m / distance_m);
    const double bearing_rad =
        geometry::wrap_angle(std::atan2(dy_m, dx_m) - first_angle_rad) + std::numbers::pi;
    for (const double turn_rad : {-2.0 * std::numbers::pi, 0.0, 2.0 * std::numbers::pi}) {
      const double relative_rad = bearing_rad - std::numbers::pi + turn_rad;
      const int first =
          std::max(0, static_cast<int>(std::ceil((relative_rad - half_width_rad) / increment_rad)));
      const int last = std::min(
          beams - 1, static_cast<int>(std::floor((relative_rad + half_width_rad) / increment_rad)));
      for (int i = first; i <= last; ++i) {
        const std::optional<double> hit =
            cast_to_circle(from, first_angle_rad + i * increment_rad, {obstacle.x_m, obstacle.y_m},
                           obstacle.radius_m);
        auto& range_m = ranges_m[static_cast<std::size_t>(i)];
        if (hit) range_m = std::min(range_m, *hit);
      }
    }
  }
}

msgs::LaserScan Simulator::read_laser() {
  msgs::LaserScan scan;
  scan.stamp_s = time_s_;
  scan.angle_min_rad = static_cast<float>(-profile_.laser_fov_rad / 2.0);
  scan.angle_increment_rad = static_cast<float>(profile_.laser_step_rad);
  scan.range_min_m = static_cast<float>(profile_.laser_range_min_m);
  scan.range_max_m = static_cast<float>(profile_.laser_range_max_m);
  scan.sensor_in_base = profile_.laser_in_base;

  const geometry::Pose2D laser = geometry::compose(pose_, profile_.laser_in_base);
  const int beams = laser_beams(profile_);
  const double first_angle_rad = laser.theta - profile_.laser_fov_rad / 2.0;
  std::vector<double> hits_m(static_cast<std::size_t>(beams));
  laser_plane_->cast_fan({laser.x, laser.y}, first_angle_rad, profile_.laser_step_rad,
                         profile_.laser_range_max_m, hits_m);
  add_obstacles_to_fan({laser.x, laser.y}, first_angle_rad, profile_.laser_step_rad, hits_m);

  scan.ranges_m.reserve(hits_m.size());
  for (const double hit_m : hits_m) {
    const double sigma_m =
        std::max(profile_.laser_range_sigma_m, profile_.laser_range_sigma_fraction * hit_m);
    const double range_m = hit_m <= profile_.laser_range_max_m
                               ? std::max(0.0, hit_m + gaussian(laser_rng_, sigma_m))
                               : profile_.laser_range_max_m + kNoReturnBeyondMax_m;
    scan.ranges_m.push_back(static_cast<float>(range_m));
  }
  return scan;
}

msgs::TiltScan Simulator::read_tilt_laser(double true_pitch_rad, double step_rad) {
  if (!(step_rad > 0.0) || !std::isfinite(true_pitch_rad)) {
    throw std::invalid_argument("tilt laser: the step must be positive and the pitch finite");
  }
  msgs::TiltScan scan;
  scan.stamp_s = time_s_;
  scan.pitch_rad = true_pitch_rad;
  scan.bearing_min_rad = 0.0;
  scan.bearing_step_rad = step_rad;
  scan.range_min_m = static_cast<float>(profile_.laser_range_min_m);
  scan.range_max_m = static_cast<float>(profile_.laser_range_max_m);
  scan.sensor_in_base = profile_.laser_in_base;
  scan.sensor_height_m = profile_.laser_height_m;

  const auto beams = static_cast<std::size_t>(std::lround(std::numbers::pi / step_rad)) + 1;
  std::vector<double> hits_m(beams);
  std::vector<Surface> surfaces(beams);
  const TiltedFan fan{geometry::compose(pose_, profile_.laser_in_base),
                      profile_.laser_height_m,
                      true_pitch_rad,
                      0.0,
                      step_rad,
                      profile_.laser_range_max_m};
  cast_tilted_fan(fan, walls_, world_.boxes, obstacles_, hits_m, surfaces);
  scan.ranges_m.reserve(beams);
  scan.intensities.reserve(beams);
  for (std::size_t k = 0; k < beams; ++k) {
    const double range_m =
        std::isfinite(hits_m[k])
            ? std::max(0.0, hits_m[k] + gaussian(tilt_rng_, profile_.laser_range_sigma_m))
            : profile_.laser_range_max_m + kNoReturnBeyondMax_m;
    scan.ranges_m.push_back(static_cast<float>(range_m));
    scan.intensities.push_back(surface_intensity(surfaces[k]));
  }
  return scan;
}

msgs::SonarRing Simulator::read_sonar() {
  msgs::SonarRing ring;
  ring.stamp_s = time_s_;
  const double half_cone_rad = profile_.sonar_cone_rad / 2.0;
  for (const geometry::Pose2D& mount : profile_.sonars_in_base) {
    const geometry::Pose2D sonar = geometry::compose(pose_, mount);
    std::optional<double> nearest;
    for (int k = 0; k < kSonarRaysPerCone; ++k) {
      const double offset_rad =
          -half_cone_rad + profile_.sonar_cone_rad * k / (kSonarRaysPerCone - 1);
      const std::optional<double> hit =
          nearest_at(*sonar_plane_, profile_.sonar_height_m, {sonar.x, sonar.y},
                     sonar.theta + offset_rad, profile_.sonar_range_max_m);
      if (hit && (!nearest || *hit < *nearest)) nearest = hit;
    }
    double range_m = profile_.sonar_range_max_m;
    if (nearest) {
      const double noisy_m = *nearest * (1.0 + gaussian(sonar_rng_, profile_.sonar_noise_fraction));
      range_m = std::clamp(noisy_m, profile_.sonar_range_min_m, profile_.sonar_range_max_m);
    }
    ring.readings.push_back({mount, profile_.sonar_cone_rad, profile_.sonar_range_min_m,
                             profile_.sonar_range_max_m, range_m});
  }
  return ring;
}

std::vector<int> Simulator::read_ir_adc() {
  std::vector<int> counts;
  counts.reserve(profile_.ir_sensors_in_base.size());
  const double half_beam_rad = profile_.ir_cone_rad / 2.0;
  for (std::size_t i = 0; i < profile_.ir_sensors_in_base.size(); ++i) {
    const geometry::Pose2D sensor = geometry::compose(pose_, profile_.ir_sensors_in_base[i]);
    std::optional<double> nearest;
    for (int k = 0; k < kIrRaysPerBeam; ++k) {
      const double offset_rad = -half_beam_rad + profile_.ir_cone_rad * k / (kIrRaysPerBeam - 1);
      const std::optional<double> hit =
          nearest_at(*ir_plane_, profile_.ir_height_m, {sensor.x, sensor.y},
                     sensor.theta + offset_rad, profile_.ir_adc.far_distance_m);
      if (hit && (!nearest || *hit < *nearest)) nearest = hit;
    }
    counts.push_back(ir_adc_.counts(i, nearest, ir_rng_));
  }
  return counts;
}

msgs::CompassReading Simulator::read_compass() {
  return {time_s_,
          geometry::wrap_angle(pose_.theta + gaussian(compass_rng_, profile_.compass_sigma_rad))};
}

msgs::LandmarkBearings Simulator::read_landmark_bearings() {
  msgs::LandmarkBearings image;
  image.stamp_s = time_s_;
  const geometry::Point2D camera{pose_.x, pose_.y};
  for (const Landmark& landmark : world_.landmarks) {
    const double dx_m = landmark.x_m - camera.x;
    const double dy_m = landmark.y_m - camera.y;
    const double distance_m = std::hypot(dx_m, dy_m);
    if (!(distance_m <= profile_.camera_range_m)) continue;
    const double direction_rad = std::atan2(dy_m, dx_m);
    // Blocked only by something in front of the cylinder's near surface.
    const double clear_m = std::max(0.0, distance_m - kLandmarkRadius_m);
    if (clear_m > 0.0 && nearest_in_plane(camera, direction_rad, clear_m)) continue;
    msgs::LandmarkBearing seen{landmark.name,
                               {landmark.x_m, landmark.y_m},
                               geometry::wrap_angle(direction_rad - pose_.theta +
                                                    gaussian(camera_rng_, profile_.bearing_sigma_rad)),
                               std::nullopt};
    if (profile_.landmark_range_sigma_m > 0.0) {
      seen.range_m = distance_m + gaussian(camera_rng_, profile_.landmark_range_sigma_m);
    }
    image.bearings.push_back(std::move(seen));
  }
  return image;
}

int Simulator::add_obstacle(double x_m, double y_m, double radius_m, double height_m) {
  if (!std::isfinite(x_m) || !std::isfinite(y_m) || !std::isfinite(radius_m) ||
      !std::isfinite(height_m) || radius_m <= 0.0 || height_m <= 0.0) {
    throw std::invalid_argument(
        "obstacle needs a finite position and a positive radius and height");
  }
  obstacles_.push_back({next_obstacle_id_, x_m, y_m, radius_m, height_m});
  return next_obstacle_id_++;
}

bool Simulator::remove_obstacle(int id) {
  const auto removed = std::remove_if(obstacles_.begin(), obstacles_.end(),
                                      [id](const Obstacle& o) { return o.id == id; });
  if (removed == obstacles_.end()) return false;
  obstacles_.erase(removed, obstacles_.end());
  return true;
}

int Simulator::add_target(const MovingTargetSpec& spec) {
  targets_.push_back({next_target_id_, MovingTarget(spec), time_s_});
  return next_target_id_++;
}

bool Simulator::remove_target(int id) {
  const auto removed = std::remove_if(targets_.begin(), targets_.end(),
                                      [id](const Target& t) { return t.id == id; });
  if (removed == targets_.end()) return false;
  targets_.erase(removed, targets_.end());
  return true;
}

std::vector<SceneSphere> Simulator::target_spheres() const {
  std::vector<SceneSphere> spheres;
  spheres.reserve(targets_.size());
  for (const Target& t : targets_) spheres.push_back(target_sphere(t.target, time_s_ - t.added_at_s));
  return spheres;
}

std::vector<SceneCylinder> Simulator::obstacle_cylinders() const {
  std::vector<SceneCylinder> cylinders;
  cylinders.reserve(obstacles_.size());
  for (const Obstacle& o : obstacles_) cylinders.push_back({o.x_m, o.y_m, o.radius_m, o.height_m});
  return cylinders;
}

msgs::HeadRange Simulator::read_head_range(const vision::PanTilt& joints) {
  msgs::HeadRange reading;
  reading.stamp_s = time_s_;
  if (!profile_.pan_tilt_camera || !head_plane_) return reading;
  const PanTiltCameraProfile& camera = *profile_.pan_tilt_camera;
  reading.range_max_m = camera.range_max_m;
  const vision::LensPosition lens = vision::PanTiltHead(camera.head).lens_in_base(joints);
  const geometry::Point2D from = geometry::transform_point(pose_, {lens.x_m, lens.y_m});
  const double centre_rad = pose_.theta + joints.pan_rad;
  std::optional<double> nearest;
  constexpr int kRays = 5;
  for (int i = 0; i < kRays; ++i) {
    const double angle_rad =
        centre_rad + camera.range_cone_rad * (static_cast<double>(i) / (kRays - 1) - 0.5);
    std::optional<double> hit = nearest_at(*head_plane_, lens.z_m, from, angle_rad,
                                           camera.range_max_m);
    for (const SceneSphere& sphere : target_spheres()) {
      const double dz_m = sphere.z_m - lens.z_m;
      if (std::abs(dz_m) >= sphere.radius_m) continue;
      const double cut_radius_m = std::sqrt(sphere.radius_m * sphere.radius_m - dz_m * dz_m);
      const std::optional<double> on_target =
          cast_to_circle(from, angle_rad, {sphere.x_m, sphere.y_m}, cut_radius_m);
      if (on_target && *on_target <= camera.range_max_m && (!hit || *on_target < *hit)) {
        hit = on_target;
      }
    }
    if (hit && (!nearest || *hit < *nearest)) nearest = hit;
  }
  if (nearest) {
    reading.range_m = std::max(0.0, *nearest + gaussian(head_range_rng_,
                                                        camera.range_noise_fraction * *nearest));
  }
  return reading;
}

}  // namespace mobot::sim
