#include "core/estimation/tricycle_motion_model.h"

#include <cmath>

namespace mobot::estimation {
namespace {

// Fraction of the step's heading change at which the translation is taken.
double heading_fraction(TricycleIntegration integration) {
  return integration == TricycleIntegration::kMidpoint ? 0.5 : 0.0;
}

}  // namespace

geometry::Pose2D tricycle_step(const geometry::Pose2D& pose, double speed_mps, double steer_rad,
                               double wheelbase_m, double dt_s, TricycleIntegration integration) {
  const double ds = speed_mps * dt_s;
  const double dtheta = ds * std::tan(steer_rad) / wheelbase_m;
  const double heading = pose.theta + heading_fraction(integration) * dtheta;
  return {pose.x + ds * std::cos(heading), pose.y + ds * std::sin(heading),
          geometry::wrap_angle(pose.theta + dtheta)};
}

TricycleJacobians tricycle_jacobians(const geometry::Pose2D& pose, double speed_mps,
                                     double steer_rad, double wheelbase_m, double dt_s,
                                     TricycleIntegration integration) {
  const double ds = speed_mps * dt_s;
  const double tan_steer = std::tan(steer_rad);
  const double cos_steer = std::cos(steer_rad);
  const double f = heading_fraction(integration);
  const double heading = pose.theta + f * ds * tan_steer / wheelbase_m;
  const double c = std::cos(heading);
  const double s = std::sin(heading);
  // d theta' / d v and d theta' / d alpha; the translation sees the fraction f of them.
  const double dtheta_dv = dt_s * tan_steer / wheelbase_m;
  const double dtheta_dsteer = ds / (wheelbase_m * cos_steer * cos_steer);
  TricycleJacobians j;
  j.a = Eigen::Matrix3d::Identity();
  j.a(0, 2) = -ds * s;
  j.a(1, 2) = ds * c;
  j.w << c * dt_s - ds * s * f * dtheta_dv, -ds * s * f * dtheta_dsteer,
      s * dt_s + ds * c * f * dtheta_dv, ds * c * f * dtheta_dsteer, dtheta_dv, dtheta_dsteer;
  return j;
}

}  // namespace mobot::estimation
