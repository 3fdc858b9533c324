#pragma once

#include <chrono>
#include <cstdint>

namespace mobot::api {

// Seconds since the Unix epoch: when a connection opened or a lock was taken, which people read
// as times of day. The robot's own time is the control loop's clock, never this.
inline double unix_now_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

// Microseconds since the Unix epoch: the stream's `wall_us`, which a client compares with its own
// clock (after estimating the offset from a pong's) to tell how old what it shows is.
inline std::int64_t wall_clock_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace mobot::api
