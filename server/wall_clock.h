#pragma once

#include <chrono>

namespace mobot::server {

// Seconds since the Unix epoch: the stamps of stored records (run starts, maps, tokens), which
// people read as dates. The robot's own time is the control loop's clock, never this.
inline double unix_now_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace mobot::server
