#include "core/kinematics/differential_model.h"

#include <stdexcept>

#include "core/kinematics/diff_drive.h"

namespace mobot::kinematics {

DifferentialModel::DifferentialModel(DifferentialModelOptions options) : options_(options) {
  if (!(options_.wheel_radius_m > 0.0) || !(options_.track_m > 0.0)) {
    throw std::invalid_argument("a differential base needs a positive wheel radius and track");
  }
}

msgs::Twist DifferentialModel::feasible(const msgs::Twist& command) const {
  return control::clamp_to_limits(command, options_.limits);
}

msgs::WheelCommand DifferentialModel::to_wheels(const msgs::Twist& body) const {
  const WheelSpeeds speeds = wheels_from_twist(body, options_.track_m);
  return {speeds.left_mps / options_.wheel_radius_m, speeds.right_mps / options_.wheel_radius_m};
}

msgs::Twist DifferentialModel::to_body(const msgs::WheelCommand& wheels) const {
  return twist_from_wheels(
      {wheels.left_radps * options_.wheel_radius_m, wheels.right_radps * options_.wheel_radius_m},
      options_.track_m);
}

}  // namespace mobot::kinematics
