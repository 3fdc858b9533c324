#pragma once

#include <random>

namespace mobot::sim {

// A first-order Gauss-Markov (Ornstein-Uhlenbeck) process x with stationary standard deviation
// sigma and correlation time tau, advanced exactly over a step of any length together with its
// mean over that step (D. T. Gillespie, "Exact numerical simulation of the Ornstein-Uhlenbeck
// process and its integral", Phys. Rev. E 54, 1996). An error that multiplies what happens during
// a step therefore accumulates the same way at 5 Hz as at 200 Hz, even when tau is shorter than
// the step.
class GaussMarkov {
 public:
  // sigma >= 0, tau > 0 (else std::invalid_argument). Starts at 0; see start().
  GaussMarkov(double sigma, double tau_s);

  // Draws the state from the stationary distribution.
  void start(std::mt19937_64& rng);
  // Advances by dt_s >= 0 and returns the mean of x over the step (x itself for dt_s = 0).
  double advance(double dt_s, std::mt19937_64& rng);

  double value() const { return x_; }
  double sigma() const { return sigma_; }

 private:
  double sigma_;
  double tau_s_;
  double x_ = 0.0;
};

}  // namespace mobot::sim
