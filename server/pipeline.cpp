#include "server/pipeline.h"

#include <algorithm>

#include "api/prometheus_text.h"

namespace mobot::server {

void Pipeline::step(TickContext& context) {
  using Clock = std::chrono::steady_clock;
  for (auto& entry : stages_) {
    const auto started = Clock::now();
    entry.stage->step(context);
    const std::int64_t ns =
        std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - started).count();
    entry.timing->total_ns.fetch_add(ns, std::memory_order_relaxed);
    if (ns > entry.timing->max_ns.load(std::memory_order_relaxed)) {
      entry.timing->max_ns.store(ns, std::memory_order_relaxed);
    }
  }
  ticks_->fetch_add(1, std::memory_order_relaxed);
}

std::vector<std::string> Pipeline::names() const {
  std::vector<std::string> out;
  for (const auto& entry : stages_) out.emplace_back(entry.stage->name());
  return out;
}

std::string Pipeline::metrics_text() const {
  const auto ticks = ticks_->load(std::memory_order_relaxed);
  std::string out;
  append_per_stage(out, "mobot_stage_seconds_mean", "Mean time of one control-tick stage.",
                   [ticks](const Timing& timing) {
                     return ticks == 0 ? 0.0
                                       : static_cast<double>(timing.total_ns.load()) /
                                             static_cast<double>(ticks) / 1e9;
                   });
  append_per_stage(
      out, "mobot_stage_seconds_max", "Longest time of one control-tick stage.",
      [](const Timing& timing) { return static_cast<double>(timing.max_ns.load()) / 1e9; });
  return out;
}

void Pipeline::append_per_stage(std::string& out, std::string_view name, std::string_view help,
                                const std::function<double(const Timing&)>& value) const {
  bool first = true;
  for (const auto& entry : stages_) {
    const std::string labels = "stage=\"" + std::string(entry.stage->name()) + "\"";
    if (first) {
      api::append_metric(out, name, "gauge", help, value(*entry.timing), labels);
    } else {
      api::append_sample(out, name, value(*entry.timing), labels);
    }
    first = false;
  }
}

}  // namespace mobot::server
