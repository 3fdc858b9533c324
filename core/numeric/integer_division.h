#pragma once

#include <cstdint>

namespace mobot {

// The quotient rounded toward minus infinity (C++'s / rounds toward zero): -7 / 2 is -4, not -3.
inline std::int64_t floor_div(std::int64_t numerator, std::int64_t denominator) {
  const std::int64_t quotient = numerator / denominator;
  return (numerator % denominator != 0 && ((numerator < 0) != (denominator < 0))) ? quotient - 1
                                                                                  : quotient;
}

}  // namespace mobot
