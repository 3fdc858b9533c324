#pragma once

#include <deque>
#include <string>
#include <vector>

namespace mobot::safety {

struct SensorStatus {
  std::string name;
  bool ok = false;
  double rate_hz = 0.0;
};

// Tracks when each sensor last delivered and how often. A sensor that has been silent for longer
// than its timeout is stale; the robot must not drive on a stale sensor it needs.
class SensorWatchdog {
 public:
  // Registers a sensor; `required` sensors stop the robot when stale.
  void add(std::string name, double timeout_s, bool required);
  void seen(const std::string& name, double t_s);
  std::vector<SensorStatus> status(double t_s) const;
  // Names of required sensors that are stale at t_s (never seen counts as stale once the
  // watchdog has run for a timeout).
  std::vector<std::string> stale_required(double t_s) const;

 private:
  struct Entry {
    std::string name;
    double timeout_s = 0.5;
    bool required = false;
    double started_s = -1.0;
    std::deque<double> recent_s;  // stamps within the last rate window
  };
  static constexpr double kRateWindow_s = 1.0;

  bool is_ok(const Entry& entry, double t_s) const;
  Entry* find(const std::string& name);

  std::vector<Entry> entries_;
  double first_t_s_ = -1.0;
};

}  // namespace mobot::safety
