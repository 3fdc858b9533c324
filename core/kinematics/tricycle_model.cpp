#include "core/kinematics/tricycle_model.h"

#include <cmath>
#include <stdexcept>

namespace mobot::kinematics {
TricycleModel::TricycleModel(TricycleModelOptions options) : options_(options) {
  const TricycleLimits& limits = options_.limits;
  if (!(options_.geometry.wheelbase_m > 0.0) || !std::isfinite(options_.geometry.wheelbase_m)) {
    throw std::invalid_argument("a tricycle needs a positive wheelbase");
  }
  if (!(limits.max_steer_rad > 0.0 && limits.max_steer_rad < 1.5) ||
      !(limits.max_linear_mps > 0.0) || !(limits.max_angular_radps > 0.0)) {
    throw std::invalid_argument(
        "a tricycle needs a steering limit in (0, 1.5) rad and positive speed limits");
  }
}

std::string_view TricycleModel::name() const {
  return options_.geometry.type == TricycleType::kType1 ? "tricycle_t1" : "tricycle_t2";
}

TricycleInput TricycleModel::input_for(const msgs::Twist& body) const {
  return tricycle_input_for(options_.geometry, body);
}

msgs::Twist TricycleModel::feasible(const msgs::Twist& command) const {
  const TricycleInput input = input_for(command);
  return tricycle_body_velocity(options_.geometry,
                                saturate(options_.geometry, options_.limits, input));
}

msgs::WheelCommand TricycleModel::to_wheels(const msgs::Twist& body) const {
  // The steering's mechanical stop and the motor's top speed hold whatever was asked.
  const TricycleInput input = saturate(options_.geometry, options_.limits, input_for(body));
  msgs::WheelCommand wheels;
  wheels.drive_mps = input.drive_mps;
  wheels.steering_rad = input.steer_rad;
  return wheels;
}

msgs::Twist TricycleModel::to_body(const msgs::WheelCommand& wheels) const {
  return tricycle_body_velocity(options_.geometry, {wheels.drive_mps, wheels.steering_rad});
}

double TricycleModel::min_turning_radius_m() const {
  return options_.geometry.wheelbase_m / std::tan(options_.limits.max_steer_rad);
}

}  // namespace mobot::kinematics
