#include "server/stages/safety_stage.h"

#include <algorithm>

namespace mobot::server {

SafetyStage::SafetyStage(const std::vector<WatchedSensor>& sensors, EndGoal end_goal)
    : end_goal_(std::move(end_goal)) {
  for (const auto& sensor : sensors) {
    watchdog_.add(sensor.name, sensor.timeout_s, sensor.required);
    if (sensor.required) required_.push_back(sensor.name);
  }
}

void SafetyStage::step(TickContext& context) {
  watch(context);
  stop_on_contacts(context);
  stop_on_faults(context);
}

void SafetyStage::watch(TickContext& context) {
  const double t_s = context.now_s;
  if (context.encoders) watchdog_.seen("encoders", t_s);
  if (context.scan) watchdog_.seen("laser", t_s);
  if (context.sonar) watchdog_.seen("sonar", t_s);
  if (context.ir) watchdog_.seen("ir", t_s);
  if (context.compass) watchdog_.seen("compass", t_s);
  if (context.head_range) watchdog_.seen("head_range", t_s);
  context.sensors.clear();
  for (const auto& status : watchdog_.status(t_s)) {
    context.sensors.push_back({status.name, status.ok, status.rate_hz, status.ok ? "" : "stale"});
  }
  for (const auto& [device, reason] : context.device_faults) {
    for (auto& sensor : context.sensors) {
      if (sensor.name == device) {
        sensor.ok = false;
        sensor.reason = reason;
      }
    }
  }
}

void SafetyStage::stop_on_contacts(TickContext& context) {
  for (const auto& contact : context.contacts) {
    contacts_.fetch_add(1, std::memory_order_relaxed);
    // The base stops and stays stopped until somebody commands it again.
    context.halt = true;
    end_goal_("collision", context);
    context.event("collision",
                  {{"with", contact.with}, {"x", contact.pose.x}, {"y", contact.pose.y}});
  }
}

void SafetyStage::stop_on_faults(TickContext& context) {
  std::vector<std::string> faults;
  for (const auto& sensor : context.sensors) {
    const bool required =
        std::find(required_.begin(), required_.end(), sensor.name) != required_.end();
    if (required && !sensor.ok) faults.push_back(sensor.name);
  }
  for (const auto& name : faults) {
    if (std::find(faults_.begin(), faults_.end(), name) != faults_.end()) continue;
    const auto sensor = std::find_if(context.sensors.begin(), context.sensors.end(),
                                     [&](const SensorState& s) { return s.name == name; });
    context.event("fault", {{"sensor", name}, {"reason", sensor->reason}});
    end_goal_("sensor_fault", context);
  }
  faults_ = faults;
  context.faults = std::move(faults);
  if (!context.faults.empty()) {
    context.mux_requests.push_back({"safety", msgs::Twist{}});
    // A robot that lost a sensor it needs stops now, not at its deceleration limit: the ramp
    // from 0.5 m/s would drive on blind for 0.4 m.
    context.halt_smoother = true;
  }
}

}  // namespace mobot::server
