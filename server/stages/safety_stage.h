#pragma once

#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "core/safety/sensor_watchdog.h"
#include "server/stage.h"

namespace mobot::server {

struct WatchedSensor {
  std::string name;
  double timeout_s = 0.5;
  bool required = false;  // its silence or fault stops the robot
};

// The layer of safety that needs no network: a contact stops the base at once and fails the goal
// ("collision"); a required sensor that falls silent or whose driver reports a fault stops the
// robot at once (no deceleration ramp) through the mux's "safety" source and fails the goal
// ("sensor_fault"). Every fault is an
// event once, when it starts.
class SafetyStage final : public Stage {
 public:
  using EndGoal = std::function<void(const std::string& reason, TickContext& context)>;

  SafetyStage(const std::vector<WatchedSensor>& sensors, EndGoal end_goal);

  std::string_view name() const override { return "safety"; }
  void step(TickContext& context) override;

  std::uint64_t contacts() const { return contacts_.load(std::memory_order_relaxed); }

 private:
  void watch(TickContext& context);
  void stop_on_contacts(TickContext& context);
  void stop_on_faults(TickContext& context);

  safety::SensorWatchdog watchdog_;
  EndGoal end_goal_;
  std::vector<std::string> required_;
  std::vector<std::string> faults_;  // as of the last tick
  std::atomic<std::uint64_t> contacts_{0};
};

}  // namespace mobot::server
