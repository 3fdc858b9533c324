#pragma once

#include "drivers/backend.h"
#include "server/stage.h"

namespace mobot::server {

// The first stage: the devices' time passes (the simulator steps its world by one period; real
// drivers collect what arrived since the last tick).
class AdvanceStage final : public Stage {
 public:
  explicit AdvanceStage(drivers::Backend& backend) : backend_(backend) {}

  std::string_view name() const override { return "advance"; }
  void step(TickContext& context) override { backend_.advance(context.period_s); }

 private:
  drivers::Backend& backend_;
};

}  // namespace mobot::server
