#include "drivers/sim/tilt_motion.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace mobot::sim {

TiltMotion::TiltMotion(perception::TiltRange range, double period_s, double ripple_fraction,
                       double ripple_period_s, double ripple_phase_rad)
    : range_(range),
      period_s_(period_s),
      ripple_fraction_(ripple_fraction),
      ripple_period_s_(ripple_period_s),
      ripple_phase_rad_(ripple_phase_rad) {
  if (!(period_s > 0.0) || !(ripple_period_s > 0.0) || !(ripple_fraction >= 0.0) ||
      !std::isfinite(period_s + ripple_period_s + ripple_fraction + ripple_phase_rad)) {
    throw std::invalid_argument("tilt motion: periods must be positive, the ripple not negative");
  }
}

double TiltMotion::pitch_rad(double elapsed_s) const {
  const double t_s = std::clamp(elapsed_s, 0.0, period_s_);
  const double nominal_speed = range_.span_rad() / period_s_;
  const double omega = 2.0 * std::numbers::pi / ripple_period_s_;
  // Integral of nominal_speed * (1 + ripple * sin(omega t + phase)) from 0 to t.
  const double ripple_integral_s =
      ripple_fraction_ / omega *
      (std::cos(ripple_phase_rad_) - std::cos(omega * t_s + ripple_phase_rad_));
  return std::min(range_.max_pitch_rad,
                  range_.min_pitch_rad + nominal_speed * (t_s + ripple_integral_s));
}

}  // namespace mobot::sim
