#pragma once

#include <cstdint>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/perception/tilt_sweep.h"

namespace mobot::sim {

// Everything the simulator needs to know about one robot: geometry, sensors, their noise, and the
// systematic errors calibration is expected to find. docs/algorithms.md R1 gives the numbers.
struct RobotProfile {
  // Nominal drive geometry: what the odometry is configured with before calibration.
  double wheel_radius_m = 0.0;
  double track_m = 0.0;
  std::int64_t ticks_per_wheel_rev = 0;

  // The body is a box centred on the base origin (the middle of the wheel axle).
  double footprint_length_m = 0.0;
  double footprint_width_m = 0.0;
  double height_m = 0.0;

  double laser_height_m = 0.0;
  geometry::Pose2D laser_in_base;
  double laser_fov_rad = 0.0;
  double laser_step_rad = 0.0;
  double laser_range_min_m = 0.0;
  double laser_range_max_m = 0.0;
  double laser_range_sigma_m = 0.0;

  // The laser nods about its left-right axis for 3D sweeps (R1): pitch range, and the tilt speed
  // loop's +/- 5 % error as a ripple of this period.
  perception::TiltRange tilt_range;
  double tilt_speed_ripple_fraction = 0.05;
  double tilt_ripple_period_s = 1.7;

  // Sonars sit in the laser plane (the simulator casts both in the same slice of the world).
  std::vector<geometry::Pose2D> sonars_in_base;
  double sonar_cone_rad = 0.0;  // full opening angle
  double sonar_range_min_m = 0.0;
  double sonar_range_max_m = 0.0;
  double sonar_noise_fraction = 0.0;  // standard deviation as a fraction of the range

  double compass_sigma_rad = 0.0;

  // Omnidirectional camera at the base centre (E2 set 3): landmarks within this range and in line
  // of sight give a bearing with this gaussian noise (the measured 2.992e-4 rad^2).
  double camera_range_m = 8.0;
  double bearing_sigma_rad = 0.017297398648;  // sqrt(2.992e-4)

  // Systematic error: true wheel radii and track as multiples of the nominal ones.
  double left_wheel_scale = 1.0;
  double right_wheel_scale = 1.0;
  double track_scale = 1.0;
  // Random wheel speed error of the on-board PID loops, as a fraction of the commanded speed. It is
  // a first-order Gauss-Markov process, so its effect does not depend on the simulation step.
  double wheel_speed_noise_fraction = 0.0;
  double wheel_speed_noise_correlation_s = 0.5;

  double max_linear_mps = 0.0;
  double max_angular_radps = 0.0;
};

// The multi-sensor differential robot of docs/algorithms.md R1.
RobotProfile r1_profile();

}  // namespace mobot::sim
