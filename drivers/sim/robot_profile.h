#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/kinematics/robot_geometry.h"
#include "core/kinematics/tricycle.h"
#include "core/perception/tilt_sweep.h"
#include "core/vision/camera_pose.h"
#include "core/vision/omni_camera_model.h"
#include "core/vision/pan_tilt_head.h"
#include "drivers/sim/camera_noise.h"
#include "drivers/sim/sharp_ir_adc.h"

namespace mobot::sim {

// A steered base (docs/algorithms.md R3): the front wheel wheelbase_m ahead of the rear axle (the
// base origin, whose two wheels carry the encoders), turned by a servo that slews at a finite rate
// and whose zero is off by a bias calibration has not found.
struct SteeringProfile {
  kinematics::TricycleType type = kinematics::TricycleType::kType2;
  double wheelbase_m = 1.84390889145857731;
  double max_steer_rad = 0.785398163397448310;
  double steer_rate_radps = 1.0;
  double steer_bias_rad = 0.0;
};

// A pinhole camera on R4's pan/tilt head with the ultrasonic ranger that looks where it looks.
struct PanTiltCameraProfile {
  vision::PanTiltHeadOptions head;
  vision::PinholeCamera camera;  // 640 x 480, 60 deg
  double rate_hz = 15.0;
  int jpeg_quality = 80;
  CameraNoiseOptions noise;
  // A Maxbotix-class ultrasonic ranger: 15 deg cone, 6 m, 1 % of the range.
  double range_cone_rad = 0.2617993877991494;
  double range_max_m = 6.0;
  double range_noise_fraction = 0.01;
  double range_rate_hz = 10.0;
};

// R1's omnidirectional camera rendered as pixels (E2 measurement 3 from the image).
struct OmniImageProfile {
  vision::OmniCameraModel model;
  double height_m = 1.0;  // the mirror's single viewpoint above the floor
  double rate_hz = 10.0;
  int jpeg_quality = 85;
  CameraNoiseOptions noise;
};

// Everything the simulator needs to know about one robot: geometry, sensors, their noise, and the
// systematic errors calibration is expected to find. docs/algorithms.md R1 and R2 give the numbers.
// A field's default is "this robot does not have it" (no slip, no IR ring) so that R1 keeps its
// numbers as new fields arrive.
struct RobotProfile {
  // Nominal drive geometry: what the odometry is configured with before calibration.
  double wheel_radius_m = 0.0;
  double track_m = 0.0;
  std::int64_t ticks_per_wheel_rev = 0;

  // The body is a box centred on the base origin (the middle of the wheel axle).
  double footprint_length_m = 0.0;
  double footprint_width_m = 0.0;
  double height_m = 0.0;
  // How far the body's centre lies ahead of the base origin.
  double footprint_offset_m = 0.0;
  // Present on a steered base; a differential base drives its two wheels.
  std::optional<SteeringProfile> steering;

  double laser_height_m = 0.0;
  geometry::Pose2D laser_in_base;
  double laser_fov_rad = 0.0;
  double laser_step_rad = 0.0;
  double laser_range_min_m = 0.0;
  double laser_range_max_m = 0.0;
  double laser_range_sigma_m = 0.0;
  // Triangulating lasers lose accuracy with range: sigma = max(laser_range_sigma_m, this * range).
  double laser_range_sigma_fraction = 0.0;

  // The laser nods about its left-right axis for 3D sweeps (R1): pitch range, and the tilt speed
  // loop's +/- 5 % error as a ripple of this period.
  perception::TiltRange tilt_range;
  double tilt_speed_ripple_fraction = 0.05;
  double tilt_ripple_period_s = 1.7;

  // Sonars see the world at their own height (R1's sit in the laser plane).
  double sonar_height_m = 0.0;
  std::vector<geometry::Pose2D> sonars_in_base;
  double sonar_cone_rad = 0.0;  // full opening angle
  double sonar_range_min_m = 0.0;
  double sonar_range_max_m = 0.0;
  double sonar_noise_fraction = 0.0;  // standard deviation as a fraction of the range

  // Infrared rangers read by a microcontroller that reports raw ADC counts (R2's Sharp ring):
  // the simulator produces the counts, the driver side converts them.
  double ir_height_m = 0.0;
  std::vector<geometry::Pose2D> ir_sensors_in_base;  // empty: no IR ring
  double ir_cone_rad = 0.0;
  double ir_rate_hz = 20.0;
  SharpIrAdcOptions ir_adc;

  // Devices the base carries; a missing one gets no driver.
  bool has_compass = true;
  bool has_omni_camera = true;
  bool has_tilt_laser = true;

  double compass_sigma_rad = 0.0;

  // Omnidirectional camera at the base centre (E2 set 3): landmarks within this range and in line
  // of sight give a bearing with this gaussian noise (the measured 2.992e-4 rad^2).
  double camera_range_m = 8.0;
  double bearing_sigma_rad = 0.017297398648;  // sqrt(2.992e-4)
  // A beacon scanner (the tricycles, E3) also measures each landmark's range with this gaussian
  // noise; 0: bearings only.
  double landmark_range_sigma_m = 0.0;
  // Cameras whose images are rendered from the world; absent: none.
  std::optional<PanTiltCameraProfile> pan_tilt_camera;
  std::optional<OmniImageProfile> omni_image;

  // Systematic error: true wheel radii and track as multiples of the nominal ones.
  double left_wheel_scale = 1.0;
  double right_wheel_scale = 1.0;
  double track_scale = 1.0;
  // Random wheel speed error of the on-board PID loops, as a fraction of the commanded speed. It is
  // a first-order Gauss-Markov process, so its effect does not depend on the simulation step.
  double wheel_speed_noise_fraction = 0.0;
  double wheel_speed_noise_correlation_s = 0.5;
  // Where the tyres meet the floor (R2): each wheel's ground travel is its turned travel times
  // (1 + n), n a Gauss-Markov process with this standard deviation and correlation time, sampled
  // exactly over each step (with its integral), so the drift does not depend on the step. The
  // encoders see the turned travel only.
  double slip_noise_fraction = 0.0;
  double slip_noise_correlation_s = 0.01;
  // A wheel's ground speed follows its turned speed no faster than this (traction): a hard start
  // spins the wheel, a hard stop skids the base on. 0: unlimited.
  double traction_accel_mps2 = 0.0;

  double max_linear_mps = 0.0;
  double max_angular_radps = 0.0;
};

// How odometry on the nominal geometry drifts from the truth, the way a base's owner measures it
// (docs/algorithms.md R2): set_odometry_errors turns it into wheel scales and slip noise.
struct OdometryErrors {
  // The odometry reads (1 + this) times the distance the base really covered (tyres compressed
  // under load roll a smaller radius than the nominal one).
  double scale_error = 0.0;
  // While the encoders count a straight line the base really turns left by this per metre
  // (unequal wheel diameters); negative turns right.
  double heading_drift_rad_per_m = 0.0;
  // slip_noise_fraction.
  double step_noise_fraction = 0.0;
};

// Sets the wheel scales (a common scale for scale_error, a left-right difference for the drift; the
// track scale stays) and the slip noise. Throws std::invalid_argument for a scale error of -1 or
// less, or a non-finite or negative noise.
void set_odometry_errors(RobotProfile& profile, const OdometryErrors& errors);
// What the profile's wheel scales and slip noise amount to.
OdometryErrors odometry_errors_of(const RobotProfile& profile);

// The drive geometry the odometry and the kinematics start from (both backends give it).
kinematics::RobotGeometry geometry_of(const RobotProfile& profile);

// The multi-sensor differential robot of docs/algorithms.md R1.
RobotProfile r1_profile();
// The Dashgo D1 of docs/algorithms.md R2.
RobotProfile dashgo_d1_profile();
// The tricycles of docs/algorithms.md R3 (type 1: the front wheel steers and drives; type 2: it
// steers, the rear wheels drive) with a laser and a landmark beacon scanner (E3).
RobotProfile tricycle_profile(kinematics::TricycleType type);
// The camera robot of docs/algorithms.md R4: a differential base (the Dashgo's) with a camera on a
// pan/tilt head and an ultrasonic ranger beside the lens.
RobotProfile camera_robot_profile();

// The robots the simulator knows, by the name robot.profile gives: one entry each.
struct NamedProfile {
  std::string_view name;
  RobotProfile (*make)();
};
std::span<const NamedProfile> robot_profiles();
// nullopt for a name not in robot_profiles().
std::optional<RobotProfile> profile_named(std::string_view name);

}  // namespace mobot::sim
