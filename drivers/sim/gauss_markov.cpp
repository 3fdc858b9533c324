#include "drivers/sim/gauss_markov.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mobot::sim {

GaussMarkov::GaussMarkov(double sigma, double tau_s) : sigma_(sigma), tau_s_(tau_s) {
  if (!std::isfinite(sigma) || sigma < 0.0 || !std::isfinite(tau_s) || !(tau_s > 0.0)) {
    throw std::invalid_argument("gauss-markov process: sigma >= 0 and tau > 0, both finite");
  }
}

void GaussMarkov::start(std::mt19937_64& rng) {
  x_ = sigma_ > 0.0 ? std::normal_distribution<double>(0.0, sigma_)(rng) : 0.0;
}

double GaussMarkov::advance(double dt_s, std::mt19937_64& rng) {
  if (!(dt_s > 0.0) || sigma_ <= 0.0) return x_;
  // Given x0, the end value x1 and the integral I over the step are jointly gaussian:
  //   E[x1] = a x0,                 Var[x1] = s^2 (1 - a^2),
  //   E[I]  = x0 tau (1 - a),       Var[I]  = s^2 tau^2 (2h - 3 + 4a - a^2),
  //   Cov[x1, I] = s^2 tau (1 - a)^2,          with h = dt / tau, a = exp(-h).
  const double h = dt_s / tau_s_;
  const double a = std::exp(-h);
  const double one_minus_a = -std::expm1(-h);
  // 2h - 3 + 4a - a^2 cancels to (2/3) h^3 for short steps: use its series there.
  const double integral_shape = h < 0.05 ? h * h * h * (2.0 / 3.0 - h / 2.0 + 7.0 * h * h / 30.0)
                                         : 2.0 * h - 3.0 + 4.0 * a - a * a;
  const double variance = sigma_ * sigma_;
  const double var_x = variance * -std::expm1(-2.0 * h);
  const double var_i = variance * tau_s_ * tau_s_ * integral_shape;
  const double cov = variance * tau_s_ * one_minus_a * one_minus_a;
  std::normal_distribution<double> unit(0.0, 1.0);
  const double n1 = unit(rng);
  const double n2 = unit(rng);
  const double sd_x = std::sqrt(var_x);
  // For very short steps the conditional variance is a difference of nearly equal numbers.
  const double conditional_var_i = std::max(0.0, var_i - (sd_x > 0.0 ? cov * cov / var_x : 0.0));
  const double integral = x_ * tau_s_ * one_minus_a + (sd_x > 0.0 ? cov / sd_x * n1 : 0.0) +
                          std::sqrt(conditional_var_i) * n2;
  x_ = a * x_ + sd_x * n1;
  return integral / dt_s;
}

}  // namespace mobot::sim
