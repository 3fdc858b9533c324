#include "server/stages/ir_safety_stage.h"

#include <string>

namespace mobot::server {

IrSafetyStage::IrSafetyStage(safety::IrSafetyOptions options, Listener on_start, Listener on_end)
    : ir_safety_(std::move(options)), on_start_(std::move(on_start)), on_end_(std::move(on_end)) {}

void IrSafetyStage::step(TickContext& context) {
  // The command is what the base was told last tick: this tick's has not been chosen yet.
  const safety::BaseMotion motion{context.command, context.odometry.twist};
  std::optional<safety::IrSafetyDecision> decision =
      ir_safety_.step(context.ir, motion, context.now_s);
  if (context.estop) {
    // Nothing may move the base under e-stop, and nothing it commands is a reaction.
    ir_safety_.reset();
    decision.reset();
  }

  if (decision) {
    context.mux_requests.push_back({"ir_safety", decision->command});
    const bool started = !active_ || active_->zone != decision->zone;
    if (started) {
      context.event("ir_safety", {{"sensor", decision->sensor},
                                  {"zone", std::string(safety::to_string(decision->zone))},
                                  {"reaction", std::string(safety::to_string(decision->reaction))},
                                  {"range_m", decision->range_m}});
      // An urgent stop cannot wait for the smoother's ramp.
      if (decision->zone == safety::IrZone::kUrgent) context.halt = true;
      if (on_start_) on_start_(*decision, context);
    }
  } else if (active_) {
    // Navigation or teleop take over at once, not after the source's time-out.
    context.mux_requests.push_back({"ir_safety", std::nullopt});
    if (on_end_) on_end_(*active_, context);
  }
  active_ = std::move(decision);
}

}  // namespace mobot::server
