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
  std::string out;
  bool first = true;
  for (const auto& entry : stages_) {
    const std::string labels = "stage=\"" + std::string(entry.stage->name()) + "\"";
    const auto ticks = ticks_->load(std::memory_order_relaxed);
    const double mean_s = ticks == 0 ? 0.0
                                     : static_cast<double>(entry.timing->total_ns.load()) /
                                           static_cast<double>(ticks) / 1e9;
    if (first) {
      api::append_metric(out, "mobot_stage_seconds_mean", "gauge",
                         "Mean time of one control-tick stage.", mean_s, labels);
    } else {
      api::append_sample(out, "mobot_stage_seconds_mean", mean_s, labels);
    }
    first = false;
  }
  first = true;
  for (const auto& entry : stages_) {
    const std::string labels = "stage=\"" + std::string(entry.stage->name()) + "\"";
    const double max_s = static_cast<double>(entry.timing->max_ns.load()) / 1e9;
    if (first) {
      api::append_metric(out, "mobot_stage_seconds_max", "gauge",
                         "Longest time of one control-tick stage.", max_s, labels);
    } else {
      api::append_sample(out, "mobot_stage_seconds_max", max_s, labels);
    }
    first = false;
  }
  return out;
}

}  // namespace mobot::server
