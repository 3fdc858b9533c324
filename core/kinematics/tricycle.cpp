#include "core/kinematics/tricycle.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace mobot::kinematics {
namespace {

using State = std::array<double, 3>;  // x, y, theta (theta not wrapped while integrating)

State derivative(const TricycleGeometry& geometry, const State& state,
                 const TricycleInput& input) {
  const msgs::Twist body = tricycle_body_velocity(geometry, input);
  return {body.linear_mps * std::cos(state[2]), body.linear_mps * std::sin(state[2]),
          body.angular_radps};
}

State advanced(const State& state, const State& slope, double h_s) {
  return {state[0] + h_s * slope[0], state[1] + h_s * slope[1], state[2] + h_s * slope[2]};
}

}  // namespace

msgs::Twist tricycle_body_velocity(const TricycleGeometry& geometry, const TricycleInput& input) {
  msgs::Twist body;
  if (geometry.type == TricycleType::kType1) {
    body.linear_mps = input.drive_mps * std::cos(input.steer_rad);
    body.angular_radps = input.drive_mps * std::sin(input.steer_rad) / geometry.wheelbase_m;
  } else {
    body.linear_mps = input.drive_mps;
    body.angular_radps = input.drive_mps * std::tan(input.steer_rad) / geometry.wheelbase_m;
  }
  return body;
}

TricycleInput tricycle_input_for(const TricycleGeometry& geometry, const msgs::Twist& body) {
  // Below this forward speed a curvature is meaningless (w / v blows up): the steering holds still.
  constexpr double kMinSpeedForCurvature_mps = 1e-6;
  const double v = body.linear_mps;
  if (!std::isfinite(v) || !std::isfinite(body.angular_radps) ||
      std::abs(v) < kMinSpeedForCurvature_mps) {
    return {};
  }
  const double steer_rad = std::atan(geometry.wheelbase_m * body.angular_radps / v);
  return {geometry.type == TricycleType::kType1 ? v / std::cos(steer_rad) : v, steer_rad};
}

TricycleInput saturate(const TricycleGeometry& geometry, const TricycleLimits& limits,
                       const TricycleInput& input) {
  if (!limits.saturate) return input;
  TricycleInput out;
  out.steer_rad = std::clamp(input.steer_rad, -limits.max_steer_rad, limits.max_steer_rad);
  out.drive_mps = std::clamp(input.drive_mps, -limits.max_linear_mps, limits.max_linear_mps);
  // v and w are both proportional to the drive speed at a fixed steering angle: one scale brings
  // the larger excess within its limit and keeps the curvature the steering asks for.
  const msgs::Twist body = tricycle_body_velocity(geometry, out);
  double scale = 1.0;
  if (std::abs(body.linear_mps) > limits.max_linear_mps) {
    scale = std::min(scale, limits.max_linear_mps / std::abs(body.linear_mps));
  }
  if (std::abs(body.angular_radps) > limits.max_angular_radps) {
    scale = std::min(scale, limits.max_angular_radps / std::abs(body.angular_radps));
  }
  out.drive_mps *= scale;
  return out;
}

geometry::Pose2D integrate_tricycle_rk4(const TricycleGeometry& geometry,
                                        const geometry::Pose2D& start,
                                        const std::function<TricycleInput(double t_s)>& input,
                                        double t0_s, double duration_s, double step_s) {
  State state{start.x, start.y, start.theta};
  if (!(duration_s > 0.0) || !(step_s > 0.0)) return start;
  const auto steps = static_cast<long>(std::ceil(duration_s / step_s));
  const double h_s = duration_s / static_cast<double>(steps);
  for (long i = 0; i < steps; ++i) {
    const double t_s = t0_s + static_cast<double>(i) * h_s;
    const TricycleInput at_start = input(t_s);
    const TricycleInput at_middle = input(t_s + h_s / 2.0);
    const State k1 = derivative(geometry, state, at_start);
    const State k2 = derivative(geometry, advanced(state, k1, h_s / 2.0), at_middle);
    const State k3 = derivative(geometry, advanced(state, k2, h_s / 2.0), at_middle);
    const State k4 = derivative(geometry, advanced(state, k3, h_s), input(t_s + h_s));
    for (std::size_t j = 0; j < 3; ++j) {
      state[j] += h_s / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
    }
  }
  // The reference poses give theta unwrapped (turns counted), as the integration carries it.
  return {state[0], state[1], state[2]};
}

}  // namespace mobot::kinematics
