#pragma once

#include "core/control/velocity_smoother.h"
#include "server/stage.h"

namespace mobot::server {

// Acceleration limits between the mux and the base; a halt (e-stop, contact, dropped commands)
// skips the ramp and stops at once.
class SmoothStage final : public Stage {
 public:
  explicit SmoothStage(const control::VelocityLimits& limits) : smoother_(limits) {}

  std::string_view name() const override { return "smooth"; }
  void step(TickContext& context) override {
    if (context.estop || context.halt || context.halt_smoother) {
      smoother_.halt();
      context.halt_smoother = false;
    } else {
      smoother_.step(context.selected, context.period_s);
    }
    context.command = smoother_.current();
  }

 private:
  control::VelocitySmoother smoother_;
};

}  // namespace mobot::server
