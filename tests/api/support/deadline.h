#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>

namespace mobot::testing {

// What is left of a deadline, in whole milliseconds for poll(2): never negative.
inline int remaining_ms(std::chrono::steady_clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
      deadline - std::chrono::steady_clock::now());
  return static_cast<int>(std::max<std::int64_t>(0, left.count()));
}

}  // namespace mobot::testing
