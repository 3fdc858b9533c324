#pragma once

#include <functional>
#include <optional>

#include "core/safety/ir_safety.h"
#include "server/stage.h"

namespace mobot::server {

// docs/algorithms.md C6 on the robot: the infrared ring's urgent zone and reactive bubble
// (safety::IrSafety) drive the mux's "ir_safety" source while a reaction runs, and let it fall
// silent the tick it ends. The first tick of a reaction is an `ir_safety` event
// {"sensor", "zone", "reaction"}; an urgent stop also halts the base at once (no ramp: the
// urgent zone is 10 cm deep). Runs after estimate (it reads the measured velocity) and before
// the mux.
class IrSafetyStage final : public Stage {
 public:
  // Called on the first tick of a reaction and on the tick it ends (then with the decision that
  // ended): the place to ask navigation for a replan ("then replan", C6).
  using Listener = std::function<void(const safety::IrSafetyDecision&, TickContext&)>;

  explicit IrSafetyStage(safety::IrSafetyOptions options = {}, Listener on_start = {},
                         Listener on_end = {});

  std::string_view name() const override { return "ir_safety"; }
  void step(TickContext& context) override;

  // The reaction running after the last step, if any.
  const std::optional<safety::IrSafetyDecision>& active() const { return active_; }

 private:
  safety::IrSafety ir_safety_;
  Listener on_start_;
  Listener on_end_;
  std::optional<safety::IrSafetyDecision> active_;
};

}  // namespace mobot::server
