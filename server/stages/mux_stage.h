#pragma once

#include <optional>
#include <vector>

#include "core/control/command_mux.h"
#include "server/stage.h"

namespace mobot::server {

// Command arbitration (docs/algorithms.md C6): applies the stages' requests, then the highest
// priority source that spoke within its time-out drives; e-stop overrides every source. Teleop
// commands arrive between ticks through submit_teleop(); a teleop that lapses while it was moving
// the robot is a `teleop_timeout` event.
class MuxStage final : public Stage {
 public:
  explicit MuxStage(std::vector<control::MuxSource> sources);

  std::string_view name() const override { return "mux"; }
  void step(TickContext& context) override;

  void submit_teleop(const msgs::Twist& command, double ttl_s, TickContext& context);
  // Engaging drops every pending command; returns the state after the request (still engaged
  // while the base's e-stop button is held down).
  bool set_estop(bool engaged, TickContext& context);
  // Forgets every pending command (e-stop, collision, reset): none of them timed out.
  void drop_commands(TickContext& context);
  bool estop() const { return estop_; }

 private:
  void note_teleop_lapse(TickContext& context);
  void write(TickContext& context) const;

  control::CommandMux mux_;
  bool estop_ = false;
  bool button_held_ = false;
  bool teleop_was_active_ = false;
  msgs::Twist last_teleop_;
};

}  // namespace mobot::server
