#include "server/stages/sonar_safety_stage.h"

#include <string>

namespace mobot::server {

SonarSafetyStage::SonarSafetyStage(safety::SonarEmergencyOptions options)
    : options_(std::move(options)) {
  // Bad options fail here, at assembly, rather than on the first tick.
  (void)safety::sonar_emergency({}, {}, options_);
}

void SonarSafetyStage::step(TickContext& context) {
  if (context.sonar) {
    ring_ = *context.sonar;
    ring_s_ = context.now_s;
  }
  active_.reset();
  if (!ring_ || context.now_s - ring_s_ > kMaxRingAge_s || context.estop) return;

  // The command is what the base was told last tick: this tick's has not been chosen yet.
  const safety::BaseMotion motion{context.command, context.odometry.twist};
  active_ = safety::sonar_emergency(*ring_, motion, options_);
  if (!active_) return;

  context.mux_requests.push_back({"safety", active_->command});
  const bool new_episode =
      last_rule_ != active_->rule || context.now_s - last_fired_s_ > kEpisodeGap_s;
  if (new_episode) {
    const std::string reaction(safety::reaction_of(active_->rule));
    context.event("sonar_safety", {{"sensor", active_->sensor},
                                   {"zone", std::string(safety::to_string(active_->rule))},
                                   {"reaction", reaction},
                                   {"range_m", active_->range_m}});
    if (reaction == "stop") context.halt = true;
  }
  last_rule_ = active_->rule;
  last_fired_s_ = context.now_s;
}

}  // namespace mobot::server
