#pragma once

#include <optional>

#include "core/safety/sonar_emergency_rules.h"
#include "server/stage.h"

namespace mobot::server {

// docs/algorithms.md R2's emergency rules on the sonar ring (safety::sonar_emergency), the last
// layer under the IR ring: while a rule fires the mux's "safety" source carries its command
// (stop, or turn away at 0.2 rad/s). The first tick of a rule is a `sonar_safety` event
// {"sensor", "zone" (the rule), "reaction"}; a stop also halts the base at once. A rule that
// stops firing is left to the source's time-out (0.2 s): the "safety" source is shared with the
// sensor watchdog, whose stop must never be cleared from here. Runs after estimate and before
// the mux; put it before the safety stage.
class SonarSafetyStage final : public Stage {
 public:
  explicit SonarSafetyStage(safety::SonarEmergencyOptions options = {});

  std::string_view name() const override { return "sonar_safety"; }
  void step(TickContext& context) override;

  const std::optional<safety::SonarEmergency>& active() const { return active_; }

 private:
  // A rule that fires again this soon after it last fired continues the same episode: the stop
  // rule refires each time the mux hands the base back, and that is one event, not four a second.
  static constexpr double kEpisodeGap_s = 1.0;
  // The ring arrives at 10 Hz; between rings the rules judge the last one, up to this old.
  static constexpr double kMaxRingAge_s = 0.3;

  safety::SonarEmergencyOptions options_;
  std::optional<msgs::SonarRing> ring_;
  double ring_s_ = 0.0;
  std::optional<safety::SonarEmergency> active_;
  std::optional<safety::SonarRule> last_rule_;
  double last_fired_s_ = -1e9;
};

}  // namespace mobot::server
