#pragma once

#include <algorithm>
#include <chrono>

namespace mobot::api {

// A rate limit: `rate_per_s` on average, `burst` at once. Refills continuously; not thread-safe
// (each connection owns its own, on its strand).
class TokenBucket {
 public:
  using Clock = std::chrono::steady_clock;

  TokenBucket(double rate_per_s, double burst, Clock::time_point now = Clock::now())
      : rate_per_s_(rate_per_s), burst_(burst), tokens_(burst), refilled_(now) {}

  // Takes one token if there is one: false when the client is over its rate.
  bool take(Clock::time_point now) {
    const double elapsed_s = std::chrono::duration<double>(now - refilled_).count();
    if (elapsed_s > 0.0) {
      tokens_ = std::min(burst_, tokens_ + elapsed_s * rate_per_s_);
      refilled_ = now;
    }
    if (tokens_ < 1.0) return false;
    tokens_ -= 1.0;
    return true;
  }

  // How long until take() succeeds again (zero when it would now).
  Clock::duration wait(Clock::time_point now) const {
    const double elapsed_s = std::chrono::duration<double>(now - refilled_).count();
    const double tokens = std::min(burst_, tokens_ + std::max(0.0, elapsed_s) * rate_per_s_);
    if (tokens >= 1.0 || rate_per_s_ <= 0.0) return Clock::duration::zero();
    return std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>((1.0 - tokens) / rate_per_s_));
  }

 private:
  double rate_per_s_;
  double burst_;
  double tokens_;
  Clock::time_point refilled_;
};

}  // namespace mobot::api
