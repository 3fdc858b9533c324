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
  // How far the footprint's centre lies ahead of the base origin (a tricycle's origin is its
  // rear-axle centre, its body reaches forward over the front wheel).
  double footprint_offset_m = 0.0;
  // A steered base's distance from the rear axle to the front wheel; 0 for a differential base.
  double wheelbase_m = 0.0;
};

}  // namespace mobot::kinematics
