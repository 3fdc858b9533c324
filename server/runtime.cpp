#include "server/runtime.h"

#include "server/stages/publish_stage.h"

namespace mobot::server {

Runtime::Runtime(Bus& bus, Pipeline pipeline, double period_s, RobotDescription robot,
                 int realtime_priority)
    : bus_(bus),
      pipeline_(std::move(pipeline)),
      period_s_(period_s),
      robot_(std::move(robot)),
      context_(bus),
      loop_(
          period_s, [this] { tick(); }, realtime_priority) {
  publish_state();
}

Runtime::~Runtime() { loop_.stop(); }

void Runtime::tick() {
  now_s_ += period_s_;
  context_.begin(now_s_, period_s_);
  pipeline_.step(context_);
  publish_state();
  // The stream's batch after the state: a frame's reader never finds older state on REST.
  bus_.flush.publish({context_.now_s});
  run_after_publish();
}

void Runtime::run_after_publish() {
  std::vector<std::function<void()>> actions;
  actions.swap(context_.after_publish);
  for (auto& action : actions) action();
}

void Runtime::post(Command command) {
  loop_.post([this, command = std::move(command)] {
    command(context_);
    publish_state();
    bus_.flush.publish({context_.now_s});
    run_after_publish();
  });
}

void Runtime::publish_state() {
  auto state = std::make_shared<RuntimeState>();
  state->robot = robot_snapshot(context_, robot_);
  state->goals = context_.goals;
  state->sweep = context_.sweep;
  state->truth = context_.truth;
  state->target = context_.target;
  state->distance_m = context_.distance_m;
  state_.store(std::move(state));
}

}  // namespace mobot::server
