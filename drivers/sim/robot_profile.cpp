#include "drivers/sim/robot_profile.h"

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace mobot::sim {
namespace {

double degrees(double angle_deg) { return angle_deg * std::numbers::pi / 180.0; }

// Four SRF05 across the front, two on each side, all on the edge of the 0.6 x 0.6 m body.
std::vector<geometry::Pose2D> r1_sonars() {
  return {
      {0.30, 0.20, degrees(45.0)},   {0.30, 0.07, degrees(15.0)},    {0.30, -0.07, degrees(-15.0)},
      {0.30, -0.20, degrees(-45.0)}, {0.15, 0.30, degrees(90.0)},    {-0.15, 0.30, degrees(90.0)},
      {0.15, -0.30, degrees(-90.0)}, {-0.15, -0.30, degrees(-90.0)},
  };
}

// The Dashgo's ten Sharp rangers on a ring of radius 0.145 m, each looking out along its radius:
// seven across the front, three across the back.
std::vector<geometry::Pose2D> dashgo_ir_ring() {
  constexpr double kRingRadius_m = 0.145;
  std::vector<geometry::Pose2D> ring;
  for (const double bearing_deg :
       {-45.0, -25.0, -10.0, 0.0, 10.0, 25.0, 45.0, 155.0, 180.0, 205.0}) {
    const double bearing_rad = geometry::wrap_angle(degrees(bearing_deg));
    ring.push_back({kRingRadius_m * std::cos(bearing_rad), kRingRadius_m * std::sin(bearing_rad),
                    bearing_rad});
  }
  return ring;
}

constexpr std::array<NamedProfile, 5> kProfiles{{
    {"r1", r1_profile},
    {"dashgo_d1", dashgo_d1_profile},
    {"tricycle_t1", [] { return tricycle_profile(kinematics::TricycleType::kType1); }},
    {"tricycle_t2", [] { return tricycle_profile(kinematics::TricycleType::kType2); }},
    {"camera_robot", camera_robot_profile},
}};

}  // namespace

void set_odometry_errors(RobotProfile& profile, const OdometryErrors& errors) {
  if (!std::isfinite(errors.scale_error) || errors.scale_error <= -1.0 ||
      !std::isfinite(errors.heading_drift_rad_per_m) ||
      !std::isfinite(errors.step_noise_fraction) || errors.step_noise_fraction < 0.0) {
    throw std::invalid_argument(
        "odometry errors: scale_error > -1, a finite heading drift and step noise >= 0");
  }
  // A straight run on equal wheel turns: the odometry reads r phi, the base covers
  // r phi (s_L + s_R) / 2 and turns r phi (s_R - s_L) / (L s_T). Solve for the mean scale from the
  // scale error and for the half-difference from the drift per metre covered.
  const double mean_scale = 1.0 / (1.0 + errors.scale_error);
  const double half_difference =
      errors.heading_drift_rad_per_m * profile.track_m * profile.track_scale * mean_scale / 2.0;
  profile.left_wheel_scale = mean_scale - half_difference;
  profile.right_wheel_scale = mean_scale + half_difference;
  profile.slip_noise_fraction = errors.step_noise_fraction;
}

OdometryErrors odometry_errors_of(const RobotProfile& profile) {
  const double mean_scale = (profile.left_wheel_scale + profile.right_wheel_scale) / 2.0;
  return {1.0 / mean_scale - 1.0,
          (profile.right_wheel_scale - profile.left_wheel_scale) /
              (profile.track_m * profile.track_scale * mean_scale),
          profile.slip_noise_fraction};
}

kinematics::RobotGeometry geometry_of(const RobotProfile& profile) {
  return {profile.wheel_radius_m,
          profile.track_m,
          static_cast<int>(profile.ticks_per_wheel_rev),
          profile.footprint_length_m,
          profile.footprint_width_m,
          profile.height_m,
          profile.footprint_offset_m,
          profile.steering ? profile.steering->wheelbase_m : 0.0};
}

RobotProfile r1_profile() {
  RobotProfile p;
  // R1 does not state the wheel size; 0.15 m wheels are typical for a 31 kg base.
  p.wheel_radius_m = 0.075;
  p.track_m = 0.60;
  // 500-slot encoder on the motor shaft, counted in quadrature (x4), behind a 19:1 gearbox.
  p.ticks_per_wheel_rev = std::int64_t{500} * 4 * 19;

  p.footprint_length_m = 0.6;
  p.footprint_width_m = 0.6;
  p.height_m = 1.2;

  p.laser_height_m = 0.4;
  p.laser_in_base = {0.2, 0.0, 0.0};
  p.laser_fov_rad = std::numbers::pi;
  p.laser_step_rad = degrees(0.5);
  p.laser_range_min_m = 0.4;
  p.laser_range_max_m = 80.0;
  p.laser_range_sigma_m = 0.01;

  p.sonar_height_m = p.laser_height_m;
  p.sonars_in_base = r1_sonars();
  p.sonar_cone_rad = degrees(22.5);
  p.sonar_range_min_m = 0.03;
  p.sonar_range_max_m = 4.0;
  p.sonar_noise_fraction = 0.02;

  // The calibrated CMPS03 variance of E2, not the datasheet's.
  p.compass_sigma_rad = std::sqrt(2.79e-4);

  // A 0.66 % radius difference bends a commanded straight line: over 7 m the robot ends about
  // 0.27 m (3.8 %) to the side while the nominal odometry still reports a straight run (E1's
  // 3.86 % before UMBmark). The track error shows up in turns.
  p.left_wheel_scale = 0.9967;
  p.right_wheel_scale = 1.0033;
  p.track_scale = 1.01;
  // The PID holds speed within +/- 5 %: treat that as about 2.5 sigma.
  p.wheel_speed_noise_fraction = 0.02;
  p.wheel_speed_noise_correlation_s = 0.5;

  p.max_linear_mps = 1.3;
  p.max_angular_radps = 2.0;
  return p;
}

RobotProfile dashgo_d1_profile() {
  RobotProfile p;
  // ROSArduinoBridge geometry: 0.128 m wheels, 0.3559 m track, 1200 ticks per wheel turn.
  p.wheel_radius_m = 0.064;
  p.track_m = 0.3559;
  p.ticks_per_wheel_rev = 1200;

  // The base is round, about 0.40 m across; the simulator's body is a box around it, tall enough
  // to carry the IR ring at 0.7 m.
  p.footprint_length_m = 0.40;
  p.footprint_width_m = 0.40;
  p.height_m = 0.75;

  // YDLIDAR G4 on the base's centre, 0.2 m above the floor: 360 deg at 0.5 deg, 0.10-16 m. Its
  // range error is about 1 cm up close and grows with range (triangulation); the datasheet's
  // resolution beyond 2 m is under 1 % of the range: sigma = max(1 cm, 0.5 % of the range).
  p.laser_height_m = 0.2;
  p.laser_in_base = {0.0, 0.0, 0.0};
  p.laser_fov_rad = 2.0 * std::numbers::pi;
  p.laser_step_rad = degrees(0.5);
  p.laser_range_min_m = 0.10;
  p.laser_range_max_m = 16.0;
  p.laser_range_sigma_m = 0.01;
  p.laser_range_sigma_fraction = 0.005;
  p.has_tilt_laser = false;

  // Four ultrasonic rangers low on the bumper, 0.1 m above the floor (chosen: low enough for a
  // doorstep or a box on the floor, which the lidar at 0.2 m misses).
  p.sonar_height_m = 0.1;
  p.sonars_in_base = {{0.18, 0.10, degrees(30.0)},
                      {0.20, 0.0, 0.0},
                      {0.18, -0.10, degrees(-30.0)},
                      {-0.20, 0.0, std::numbers::pi}};
  p.sonar_cone_rad = 0.3;
  p.sonar_range_min_m = 0.03;
  p.sonar_range_max_m = 0.8;
  p.sonar_noise_fraction = 0.02;

  p.ir_height_m = 0.7;
  p.ir_sensors_in_base = dashgo_ir_ring();
  p.ir_cone_rad = 0.1;
  p.ir_rate_hz = 20.0;

  // No compass, no omnidirectional camera on this base.
  p.has_compass = false;
  p.has_omni_camera = false;
  p.camera_range_m = 0.0;

  // The drive PID at 30 Hz holds the wheel speed within a few percent.
  p.wheel_speed_noise_fraction = 0.02;
  p.wheel_speed_noise_correlation_s = 0.5;
  // Odometry alone drifts like a light base on a hard floor: 1 % long, 0.004 rad/m to the left,
  // 3 % noise per wheel with a 10 ms correlation (as an independent 3 % error on every 20 ms
  // step at 50 Hz would, but the same at every step length). With about 60 % of the weight on
  // the drive wheels and a friction of 0.5 they grip up to 3 m/s^2 (chosen), so only a halt (a
  // stop without the 0.3 m/s^2 ramp) slides.
  set_odometry_errors(p, {0.01, 0.004, 0.03});
  p.slip_noise_correlation_s = 0.01;
  p.traction_accel_mps2 = 3.0;

  p.max_linear_mps = 0.5;
  p.max_angular_radps = 0.7;
  return p;
}

RobotProfile tricycle_profile(kinematics::TricycleType type) {
  RobotProfile p;
  // R3 at the source's scale G = 9: wheelbase sqrt(3.4) m, a small utility vehicle. The rear axle
  // (the reference point) carries two 0.25 m wheels 1.0 m apart with 2048-line encoders in
  // quadrature; on type 1 they roll freely, on type 2 they drive through a differential.
  p.wheel_radius_m = 0.25;
  p.track_m = 1.0;
  p.ticks_per_wheel_rev = 2048 * 4;
  SteeringProfile steering;
  steering.type = type;
  // A steering servo needs about 0.8 s from lock to lock; its zero sits 0.5 deg off (chosen: a
  // mechanic's alignment, well inside the 5 deg that breaks open-loop tracking in C3).
  steering.steer_rate_radps = 2.0;
  steering.steer_bias_rad = degrees(0.5);
  p.steering = steering;

  // From 0.4 m behind the rear axle to 0.4 m past the front wheel, 1.2 m wide, 1.0 m tall.
  p.footprint_length_m = steering.wheelbase_m + 0.8;
  p.footprint_width_m = 1.2;
  p.footprint_offset_m = steering.wheelbase_m / 2.0;
  p.height_m = 1.0;

  // A 270 deg outdoor laser scanner on the front bumper, 0.5 deg steps, 30 m.
  p.laser_height_m = 0.5;
  p.laser_in_base = {steering.wheelbase_m + 0.35, 0.0, 0.0};
  p.laser_fov_rad = degrees(270.0);
  p.laser_step_rad = degrees(0.5);
  p.laser_range_min_m = 0.1;
  p.laser_range_max_m = 30.0;
  p.laser_range_sigma_m = 0.02;
  p.has_tilt_laser = false;

  // No sonar ring: the laser covers the front; the profile still names a range for the validator.
  p.sonar_height_m = 0.5;
  p.sonar_range_max_m = 4.0;

  // The landmark scanner measures range and bearing to the world's beacons with E3's sigmas.
  p.has_compass = false;
  p.has_omni_camera = true;
  p.camera_range_m = 25.0;
  p.bearing_sigma_rad = degrees(2.0);
  p.landmark_range_sigma_m = 0.1;

  // A wheel-speed loop as good as R1's, a tyre scale error of 0.5 % and a slight left pull.
  p.wheel_speed_noise_fraction = 0.02;
  p.wheel_speed_noise_correlation_s = 0.5;
  set_odometry_errors(p, {0.005, 0.002, 0.0});

  // R3's limits: 1.77 m/s and 0.3 rad/s; the body turns no faster than its steering allows.
  p.max_linear_mps = 1.77;
  p.max_angular_radps = 0.3;
  return p;
}

RobotProfile camera_robot_profile() {
  // R4 gives the chain, not the base: the Dashgo's drive, lidar and sonars carry the head.
  RobotProfile p = dashgo_d1_profile();
  p.ir_sensors_in_base.clear();
  PanTiltCameraProfile camera;
  camera.head.l0_m = 0.45;  // the head's column stands above the lidar
  camera.head.mount_x_m = 0.05;
  p.pan_tilt_camera = camera;
  p.height_m = camera.head.l0_m + camera.head.l1_m + 0.1;
  // Fast enough to keep up with a person walking (R4 follows people): 1 m/s, 1.5 rad/s.
  p.max_linear_mps = 1.0;
  p.max_angular_radps = 1.5;
  return p;
}

std::span<const NamedProfile> robot_profiles() { return kProfiles; }

std::optional<RobotProfile> profile_named(std::string_view name) {
  for (const NamedProfile& entry : kProfiles) {
    if (entry.name == name) return entry.make();
  }
  return std::nullopt;
}

}  // namespace mobot::sim
