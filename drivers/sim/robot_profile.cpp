#include "drivers/sim/robot_profile.h"

#include <cmath>
#include <numbers>

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

}  // namespace

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

}  // namespace mobot::sim
