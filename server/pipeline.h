#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "server/stage.h"

namespace mobot::server {

// The control tick as an ordered list of named stages. Measures each stage's time for /metrics.
// step() runs on the control loop; metrics_text() may be called from any thread.
class Pipeline {
 public:
  // Appends `stage` and returns it, for the caller to keep a handle on its commands.
  template <class S>
  S& add(std::unique_ptr<S> stage) {
    S& ref = *stage;
    stages_.push_back({std::move(stage), std::make_unique<Timing>()});
    return ref;
  }

  void step(TickContext& context);
  std::vector<std::string> names() const;
  std::string metrics_text() const;

 private:
  struct Timing {
    std::atomic<std::int64_t> total_ns{0};
    std::atomic<std::int64_t> max_ns{0};
  };
  struct Entry {
    std::unique_ptr<Stage> stage;
    std::unique_ptr<Timing> timing;
  };
  void append_per_stage(std::string& out, std::string_view name, std::string_view help,
                        const std::function<double(const Timing&)>& value) const;

  std::vector<Entry> stages_;
  std::unique_ptr<std::atomic<std::uint64_t>> ticks_ =
      std::make_unique<std::atomic<std::uint64_t>>(0);
};

}  // namespace mobot::server
