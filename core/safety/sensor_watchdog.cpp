#include "core/safety/sensor_watchdog.h"

#include <algorithm>

namespace mobot::safety {

void SensorWatchdog::add(std::string name, double timeout_s, bool required) {
  entries_.push_back({std::move(name), timeout_s, required, -1.0, {}});
}

SensorWatchdog::Entry* SensorWatchdog::find(const std::string& name) {
  auto it = std::find_if(entries_.begin(), entries_.end(),
                         [&](const Entry& entry) { return entry.name == name; });
  return it == entries_.end() ? nullptr : &*it;
}

void SensorWatchdog::seen(const std::string& name, double t_s) {
  if (first_t_s_ < 0.0) first_t_s_ = t_s;
  Entry* entry = find(name);
  if (entry == nullptr) return;
  entry->recent_s.push_back(t_s);
  while (!entry->recent_s.empty() && entry->recent_s.front() <= t_s - kRateWindow_s) {
    entry->recent_s.pop_front();
  }
}

bool SensorWatchdog::is_ok(const Entry& entry, double t_s) const {
  if (entry.recent_s.empty()) return false;
  return t_s - entry.recent_s.back() <= entry.timeout_s;
}

std::vector<SensorStatus> SensorWatchdog::status(double t_s) const {
  std::vector<SensorStatus> out;
  out.reserve(entries_.size());
  for (const auto& entry : entries_) {
    const auto in_window = std::count_if(entry.recent_s.begin(), entry.recent_s.end(),
                                         [&](double stamp) { return stamp > t_s - kRateWindow_s; });
    out.push_back({entry.name, is_ok(entry, t_s), static_cast<double>(in_window) / kRateWindow_s});
  }
  return out;
}

std::vector<std::string> SensorWatchdog::stale_required(double t_s) const {
  std::vector<std::string> stale;
  for (const auto& entry : entries_) {
    if (!entry.required || is_ok(entry, t_s)) continue;
    // A sensor that has not reported yet gets one timeout of grace after start-up.
    if (entry.recent_s.empty() && first_t_s_ >= 0.0 && t_s - first_t_s_ <= entry.timeout_s) {
      continue;
    }
    stale.push_back(entry.name);
  }
  return stale;
}

}  // namespace mobot::safety
