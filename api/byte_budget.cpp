#include "api/byte_budget.h"

#include <algorithm>

namespace mobot::api {
namespace {

// The burst: half a second at the rate, but at least one large frame's worth (a scan of a
// 360-degree lidar, a small JPEG), or nothing but the state would ever go on a very thin cap.
constexpr double kBurstSeconds = 0.5;
constexpr double kMinBurstBytes = 16 * 1024;

}  // namespace

void ByteBudget::set_rate(double bytes_per_s, Clock::time_point now) {
  rate_bytes_per_s_ = std::max(0.0, bytes_per_s);
  burst_bytes_ = std::max(kMinBurstBytes, kBurstSeconds * rate_bytes_per_s_);
  balance_bytes_ = burst_bytes_;
  refilled_ = now;
}

void ByteBudget::refill(Clock::time_point now) {
  const double elapsed_s = std::chrono::duration<double>(now - refilled_).count();
  if (elapsed_s <= 0.0) return;
  balance_bytes_ = std::min(burst_bytes_, balance_bytes_ + elapsed_s * rate_bytes_per_s_);
  refilled_ = now;
}

bool ByteBudget::take(std::size_t bytes, TopicPriority priority, Clock::time_point now) {
  if (!capped()) return true;
  refill(now);
  const auto size = static_cast<double>(bytes);
  const double needed = priority == TopicPriority::kState  ? -1e300
                        : priority == TopicPriority::kSensor ? size
                                                             : size + burst_bytes_ / 2.0;
  if (balance_bytes_ < needed) return false;
  balance_bytes_ -= size;
  return true;
}

}  // namespace mobot::api
