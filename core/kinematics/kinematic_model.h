#pragma once

#include <string_view>

#include "core/msgs/twist.h"
#include "core/msgs/wheel_command.h"

namespace mobot::kinematics {

// How a base turns wheel speeds into motion: one implementation per drive (differential now,
// the tricycles next), chosen by the config's robot.kinematics.
class KinematicModel {
 public:
  virtual ~KinematicModel() = default;
  virtual std::string_view name() const = 0;

  // The body velocity the base can actually follow that is closest to `command` (speed limits,
  // and for a steered base its steering limits).
  virtual msgs::Twist feasible(const msgs::Twist& command) const = 0;
  // Inverse kinematics: the wheel command that yields the body velocity.
  virtual msgs::WheelCommand to_wheels(const msgs::Twist& body) const = 0;
  // Forward kinematics: the body velocity the wheel command yields.
  virtual msgs::Twist to_body(const msgs::WheelCommand& wheels) const = 0;
  // Whether the base steers a wheel (its WheelCommand's steering_rad means something).
  virtual bool steered() const { return false; }
  // The tightest turn the base can drive; 0 for one that turns on the spot.
  virtual double min_turning_radius_m() const { return 0.0; }
};

}  // namespace mobot::kinematics
