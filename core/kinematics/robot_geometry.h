#pragma once

namespace mobot::kinematics {

// The base's dimensions that the navigation core needs, whatever drives it.
struct RobotGeometry {
  double wheel_radius_m = 0.0;
  double track_m = 0.0;  // distance between the drive wheels' contact points
  int ticks_per_wheel_rev = 0;
  double footprint_length_m = 0.0;
  double footprint_width_m = 0.0;
  double height_m = 0.0;
};

}  // namespace mobot::kinematics
