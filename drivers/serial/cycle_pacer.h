#pragma once

#include <chrono>
#include <thread>

namespace mobot::drivers::serial {

// Paces a device thread's polling cycle at a fixed rate. A cycle that ran late is not made up
// for with a burst: the next one starts a period after it.
class CyclePacer {
 public:
  using Clock = std::chrono::steady_clock;

  explicit CyclePacer(double rate_hz)
      : period_(std::chrono::duration_cast<Clock::duration>(
            std::chrono::duration<double>(1.0 / rate_hz))),
        next_(Clock::now()) {}

  // Sleeps until the next cycle is due.
  void wait_next() {
    next_ += period_;
    const auto now = Clock::now();
    if (next_ < now) next_ = now;
    std::this_thread::sleep_until(next_);
  }

 private:
  Clock::duration period_;
  Clock::time_point next_;
};

}  // namespace mobot::drivers::serial
