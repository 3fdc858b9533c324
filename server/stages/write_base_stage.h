#pragma once

#include "core/kinematics/kinematic_model.h"
#include "drivers/base_driver.h"
#include "server/stage.h"

namespace mobot::server {

// The smoothed body velocity, through the kinematic model, to the base's wheel set-points.
class WriteBaseStage final : public Stage {
 public:
  WriteBaseStage(drivers::BaseDriver& base, const kinematics::KinematicModel& model)
      : base_(base), model_(model) {}

  std::string_view name() const override { return "write_base"; }
  void step(TickContext& context) override {
    const msgs::WheelCommand wheels = model_.to_wheels(context.command);
    base_.set_wheel_command(wheels);
    if (model_.steered()) context.steering_rad = wheels.steering_rad;
  }
  // Zero at once, without waiting for a tick: e-stop and shutdown.
  void stop_now() { base_.set_wheel_command({}); }

 private:
  drivers::BaseDriver& base_;
  const kinematics::KinematicModel& model_;
};

}  // namespace mobot::server
