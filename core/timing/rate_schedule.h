#pragma once

#include <limits>

namespace mobot::timing {

// When a periodic reading (a sensor at its own rate, the status topic, a trajectory sample) is due
// on the robot clock. Readings are taken on control ticks, so the schedule keeps the nominal
// phase (due times k * period apart) and re-anchors only after a reading was missed entirely,
// which keeps stamps exactly one period apart instead of drifting with the tick granularity.
class RateSchedule {
 public:
  explicit RateSchedule(double period_s) : period_s_(period_s) {}

  bool due(double now_s) const { return now_s + kSlack_s >= due_s_; }
  // Marks the reading taken at now_s and schedules the next one.
  void taken(double now_s) {
    due_s_ = due_s_ + period_s_ > now_s + kSlack_s ? due_s_ + period_s_ : now_s + period_s_;
  }
  double period_s() const { return period_s_; }

 private:
  // Tick times are sums of a period that is not exact in binary.
  static constexpr double kSlack_s = 1e-9;
  double period_s_;
  double due_s_ = -std::numeric_limits<double>::infinity();
};

}  // namespace mobot::timing
