#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "server/bus.h"
#include "server/control_loop.h"
#include "server/latest.h"
#include "server/map_listener.h"
#include "server/pipeline.h"
#include "server/runtime_state.h"
#include "server/stages/publish_stage.h"
#include "server/tick_context.h"

namespace mobot::server {

// The control loop's side of the server: the pipeline of stages run once per period, the
// commands the network posts (run between ticks, on the same thread, so the stages need no
// locks), and the immutable state published after each tick and each command.
class Runtime {
 public:
  using Command = std::function<void(TickContext&)>;

  // `realtime_priority`: see ControlLoop.
  Runtime(Bus& bus, Pipeline pipeline, double period_s, RobotDescription robot,
          int realtime_priority = 0);
  ~Runtime();
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;

  void start(double time_scale) { loop_.start(time_scale); }
  void stop() { loop_.stop(); }
  void set_time_scale(double time_scale) { loop_.set_time_scale(time_scale); }

  // Runs `command` on the control loop between ticks, then publishes the state and flushes the
  // bus. Any thread; never blocks.
  void post(Command command);
  // One tick now, on the caller's thread: for tests and benchmarks that drive the loop by hand.
  void tick();
  // Runs the commands posted so far on the caller's thread (the loop must not be started).
  void run_posted() { loop_.run_ready(); }

  std::shared_ptr<const RuntimeState> state() const { return state_.load(); }
  double period_s() const { return period_s_; }
  std::string metrics_text() const { return loop_.metrics_text() + pipeline_.metrics_text(); }
  std::vector<std::string> stage_names() const { return pipeline_.names(); }

 private:
  void publish_state();
  void run_after_publish();

  Bus& bus_;
  Pipeline pipeline_;
  const double period_s_;
  const RobotDescription robot_;
  TickContext context_;
  // The robot clock: advances one period per tick and never goes back (not even when the
  // simulator restarts), so the trajectory, the watchdog and the stream stamps stay monotonic.
  double now_s_ = 0.0;
  Latest<RuntimeState> state_;
  ControlLoop loop_;
};

}  // namespace mobot::server
