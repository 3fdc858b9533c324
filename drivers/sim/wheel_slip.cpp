#include "drivers/sim/wheel_slip.h"

#include <cmath>
#include <stdexcept>

namespace mobot::sim {
namespace {

const WheelSlipOptions& checked(const WheelSlipOptions& options) {
  if (!std::isfinite(options.noise_fraction) || options.noise_fraction < 0.0 ||
      !std::isfinite(options.traction_accel_mps2) || options.traction_accel_mps2 < 0.0) {
    throw std::invalid_argument("wheel slip: noise and traction must be finite and >= 0");
  }
  return options;
}

}  // namespace

WheelSlip::WheelSlip(const WheelSlipOptions& options)
    : options_(checked(options)),
      left_noise_(options.noise_fraction, options.noise_correlation_s),
      right_noise_(options.noise_fraction, options.noise_correlation_s) {}

bool WheelSlip::enabled() const {
  return options_.noise_fraction > 0.0 || options_.traction_accel_mps2 > 0.0;
}

void WheelSlip::reset(std::mt19937_64& rng) {
  left_ground_mps_ = 0.0;
  right_ground_mps_ = 0.0;
  left_noise_.start(rng);
  right_noise_.start(rng);
}

void WheelSlip::stop() {
  left_ground_mps_ = 0.0;
  right_ground_mps_ = 0.0;
}

double WheelSlip::follow(double& ground_mps, double wheel_mps, double dt_s) const {
  const double accel = options_.traction_accel_mps2;
  if (accel <= 0.0) {
    ground_mps = wheel_mps;
    return wheel_mps * dt_s;
  }
  const double gap_mps = wheel_mps - ground_mps;
  const double direction = gap_mps >= 0.0 ? 1.0 : -1.0;
  const double catch_up_s = std::abs(gap_mps) / accel;
  if (catch_up_s >= dt_s) {
    const double travel_m = ground_mps * dt_s + direction * accel * dt_s * dt_s / 2.0;
    ground_mps += direction * accel * dt_s;
    return travel_m;
  }
  const double travel_m = ground_mps * catch_up_s +
                          direction * accel * catch_up_s * catch_up_s / 2.0 +
                          wheel_mps * (dt_s - catch_up_s);
  ground_mps = wheel_mps;
  return travel_m;
}

WheelSlip::Travel WheelSlip::step(double left_mps, double right_mps, double dt_s,
                                  std::mt19937_64& rng) {
  const double left_m = follow(left_ground_mps_, left_mps, dt_s);
  const double right_m = follow(right_ground_mps_, right_mps, dt_s);
  // Both processes advance every step, moving or not, so their draws do not depend on the path.
  const double left_error = left_noise_.advance(dt_s, rng);
  const double right_error = right_noise_.advance(dt_s, rng);
  return {left_m * (1.0 + left_error), right_m * (1.0 + right_error)};
}

}  // namespace mobot::sim
