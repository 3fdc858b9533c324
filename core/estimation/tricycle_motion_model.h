#pragma once

#include <Eigen/Core>

#include "core/geometry/pose2d.h"

namespace mobot::estimation {

// How one prediction step integrates the heading.
enum class TricycleIntegration {
  // docs/algorithms.md E3 as written: explicit Euler, the step follows the heading at its start.
  kEuler,
  // The step follows the mid-step heading, like E1's odometry: second-order accurate on arcs.
  kMidpoint,
};

// The prediction model of docs/algorithms.md E3: a type 2 tricycle (front wheel steers, rear wheels
// drive; reference point the rear-axle centre) advanced by one step of dt_s:
// theta += v dt tan(alpha) / d, x += v dt cos(h), y += v dt sin(h) with h the start heading
// (kEuler) or the mid-step heading (kMidpoint).
geometry::Pose2D tricycle_step(const geometry::Pose2D& pose, double speed_mps, double steer_rad,
                               double wheelbase_m, double dt_s,
                               TricycleIntegration integration = TricycleIntegration::kEuler);

// Its Jacobians: A = d pose' / d pose and W = d pose' / d (v, alpha). For kEuler, W is E3's
// [[c dt, 0], [s dt, 0], [tan(alpha) dt / d, v dt / (d cos^2(alpha))]].
struct TricycleJacobians {
  Eigen::Matrix3d a;
  Eigen::Matrix<double, 3, 2> w;
};

TricycleJacobians tricycle_jacobians(const geometry::Pose2D& pose, double speed_mps,
                                     double steer_rad, double wheelbase_m, double dt_s,
                                     TricycleIntegration integration = TricycleIntegration::kEuler);

}  // namespace mobot::estimation
