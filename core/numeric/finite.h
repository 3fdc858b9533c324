#pragma once

#include <cmath>

namespace mobot {

// The checks of options and readings: NaN and the infinities fail both, so a single comparison
// cannot let them through (NaN > 0 is false, but so is NaN <= 0).
inline bool finite_positive(double value) { return std::isfinite(value) && value > 0.0; }
inline bool finite_non_negative(double value) { return std::isfinite(value) && value >= 0.0; }

}  // namespace mobot
