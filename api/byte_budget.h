#pragma once

#include <chrono>
#include <cstddef>

#include "api/stream_topics.h"

namespace mobot::api {

// A client's max_kbps: the bytes it may be sent, refilled continuously at the rate, up to half a
// second's worth at once. The robot's state (pose, status, events, ...) is charged but never held
// back: the budget may go into debt, and the sensor topics wait until it is paid. A sensor frame
// goes when its size is in the budget; a bulk frame (camera, cloud, map) when its size and half
// the burst are, so that the bulk never takes what the sensors need. Not thread-safe.
class ByteBudget {
 public:
  using Clock = std::chrono::steady_clock;

  // `bytes_per_s` 0: no cap.
  void set_rate(double bytes_per_s, Clock::time_point now);
  bool capped() const { return rate_bytes_per_s_ > 0.0; }

  // Whether a frame of `bytes` of a topic of `priority` goes now; charged when it does.
  bool take(std::size_t bytes, TopicPriority priority, Clock::time_point now);

 private:
  void refill(Clock::time_point now);

  double rate_bytes_per_s_ = 0.0;
  double burst_bytes_ = 0.0;
  double balance_bytes_ = 0.0;
  Clock::time_point refilled_{};
};

}  // namespace mobot::api
