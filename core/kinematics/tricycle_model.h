#pragma once

#include "core/kinematics/kinematic_model.h"
#include "core/kinematics/tricycle.h"

namespace mobot::kinematics {

struct TricycleModelOptions {
  TricycleGeometry geometry;
  TricycleLimits limits;
};

// A tricycle (docs/algorithms.md R3) behind the KinematicModel interface: a body velocity (v, w)
// asks for the curvature k = w / v, which the steering angle alpha = atan(d k) gives for both
// types; the driven wheel's speed then follows from v. It cannot turn on the spot: a command with
// no forward speed does not turn.
class TricycleModel final : public KinematicModel {
 public:
  explicit TricycleModel(TricycleModelOptions options);

  std::string_view name() const override;
  // Within R3's limits when saturation is on: |alpha| <= max_steer, |v| <= max_linear,
  // |w| <= max_angular (the speed is lowered to keep the asked curvature where the steering can
  // give it).
  msgs::Twist feasible(const msgs::Twist& command) const override;
  msgs::WheelCommand to_wheels(const msgs::Twist& body) const override;
  msgs::Twist to_body(const msgs::WheelCommand& wheels) const override;
  bool steered() const override { return true; }

  // The tricycle input that yields `body` (no limits applied).
  TricycleInput input_for(const msgs::Twist& body) const;
  const TricycleModelOptions& options() const { return options_; }
  // d / tan(max_steer): the steering's mechanical stop holds with saturation off too.
  double min_turning_radius_m() const override;

 private:
  TricycleModelOptions options_;
};

}  // namespace mobot::kinematics
