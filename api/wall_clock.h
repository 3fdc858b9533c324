#pragma once

#include <chrono>

namespace mobot::api {

// Seconds since the Unix epoch: when a connection opened or a lock was taken, which people read
// as times of day. The robot's own time is the control loop's clock, never this.
inline double unix_now_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace mobot::api
