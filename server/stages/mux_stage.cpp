#include "server/stages/mux_stage.h"

namespace mobot::server {

MuxStage::MuxStage(std::vector<control::MuxSource> sources) : mux_(std::move(sources)) {}

void MuxStage::step(TickContext& context) {
  // The base's own red button engages the e-stop, and holds it while it is down; the API
  // releases it once the button is up.
  button_held_ = context.estop_button;
  if (button_held_ && !estop_) {
    estop_ = true;
    drop_commands(context);
    context.event("estop", {{"engaged", true}, {"source", "button"}});
  }
  for (const auto& request : context.mux_requests) {
    // Nothing commanded under e-stop may drive the robot when it is released.
    if (request.command && !estop_) {
      mux_.submit(request.source, *request.command, context.now_s);
    } else if (!request.command) {
      mux_.clear(request.source);
    }
  }
  if (context.halt) drop_commands(context);
  note_teleop_lapse(context);
  write(context);
}

void MuxStage::note_teleop_lapse(TickContext& context) {
  const bool teleop_active = mux_.is_active("teleop", context.now_s);
  if (teleop_was_active_ && !teleop_active &&
      (last_teleop_.linear_mps != 0.0 || last_teleop_.angular_radps != 0.0)) {
    context.event("teleop_timeout", {{"ttl_expired", true}});
    last_teleop_ = {};
  }
  teleop_was_active_ = teleop_active;
}

void MuxStage::write(TickContext& context) const {
  context.estop = estop_;
  context.teleop_active = mux_.is_active("teleop", context.now_s);
  const control::CommandMux::Selection selection = mux_.select(context.now_s);
  context.mux_source = estop_ ? std::nullopt : selection.source;
  context.selected = estop_ ? msgs::Twist{} : selection.command;
}

void MuxStage::submit_teleop(const msgs::Twist& command, double ttl_s, TickContext& context) {
  mux_.submit("teleop", command, context.now_s, ttl_s);
  last_teleop_ = command;
  write(context);
}

bool MuxStage::set_estop(bool engaged, TickContext& context) {
  if (engaged != estop_ && (engaged || !button_held_)) {
    estop_ = engaged;
    if (engaged) drop_commands(context);
    context.event("estop", {{"engaged", engaged}});
  }
  write(context);
  return estop_;
}

void MuxStage::drop_commands(TickContext& context) {
  mux_.clear_all();
  // A command dropped on purpose did not time out: no teleop_timeout.
  last_teleop_ = {};
  teleop_was_active_ = false;
  context.halt_smoother = true;
  write(context);
}

}  // namespace mobot::server
