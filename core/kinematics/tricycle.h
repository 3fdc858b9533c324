#pragma once

#include <functional>

#include "core/geometry/pose2d.h"
#include "core/msgs/twist.h"

namespace mobot::kinematics {

// The two tricycles of docs/algorithms.md R3. The reference point is the rear-axle centre, d the
// wheelbase, alpha the front wheel's steering angle, V_c the driven wheel's ground speed.
enum class TricycleType {
  kType1,  // the front wheel steers and drives: v = V_c cos(alpha), w = V_c sin(alpha) / d
  kType2,  // the front wheel steers, the rear wheels drive: v = V_c, w = V_c tan(alpha) / d
};

// The tricycle's drive command: the driven wheel's speed and the steering angle.
struct TricycleInput {
  double drive_mps = 0.0;  // V_c
  double steer_rad = 0.0;  // alpha
};

// R3's limits (G = 9 of the source). The source does not say it enforced them, so saturation is
// switchable: off, the inputs pass as they are.
struct TricycleLimits {
  bool saturate = true;
  double max_linear_mps = 1.77;
  double max_steer_rad = 0.785398163397448310;  // pi / 4
  double max_angular_radps = 0.3;
  double max_accel_mps2 = 0.29;
};

struct TricycleGeometry {
  TricycleType type = TricycleType::kType2;
  double wheelbase_m = 1.84390889145857731;  // sqrt(3.4)
};

// The body velocity (v, w) of the reference point for an input.
msgs::Twist tricycle_body_velocity(const TricycleGeometry& geometry, const TricycleInput& input);

// The input that yields the body velocity (no limits): both types steer to tan(alpha) = d w / v;
// type 1's driven wheel runs v / cos(alpha). A body velocity without forward speed has none (a
// tricycle cannot turn on the spot): zero.
TricycleInput tricycle_input_for(const TricycleGeometry& geometry, const msgs::Twist& body);

// The input clamped to the steering and speed limits, then scaled down (speed only, the steering
// kept) until |v| and |w| are within theirs; unchanged when saturation is off. The acceleration
// limit belongs to whoever ramps the speed over time (the smoother).
TricycleInput saturate(const TricycleGeometry& geometry, const TricycleLimits& limits,
                       const TricycleInput& input);

// The pose after `duration_s` from `start` at t = t0_s under the time-varying input `input(t)`,
// integrated by classical fourth-order Runge-Kutta in steps of at most `step_s` (the source's
// reference trajectories are computed so).
geometry::Pose2D integrate_tricycle_rk4(const TricycleGeometry& geometry,
                                        const geometry::Pose2D& start,
                                        const std::function<TricycleInput(double t_s)>& input,
                                        double t0_s, double duration_s, double step_s);

}  // namespace mobot::kinematics
