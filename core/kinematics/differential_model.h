#pragma once

#include "core/control/velocity_limits.h"
#include "core/kinematics/kinematic_model.h"

namespace mobot::kinematics {

struct DifferentialModelOptions {
  double wheel_radius_m = 0.1;
  double track_m = 0.5;
  control::VelocityLimits limits;
};

// Two driven wheels on one axle: v = r (w_r + w_l) / 2, w = r (w_r - w_l) / track.
class DifferentialModel final : public KinematicModel {
 public:
  explicit DifferentialModel(DifferentialModelOptions options);

  std::string_view name() const override { return "differential"; }
  msgs::Twist feasible(const msgs::Twist& command) const override;
  msgs::WheelCommand to_wheels(const msgs::Twist& body) const override;
  msgs::Twist to_body(const msgs::WheelCommand& wheels) const override;

 private:
  DifferentialModelOptions options_;
};

}  // namespace mobot::kinematics
