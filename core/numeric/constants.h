#pragma once

#include <limits>
#include <numbers>

namespace mobot {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();
inline constexpr double kTwoPi = 2.0 * std::numbers::pi;
inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;

}  // namespace mobot
