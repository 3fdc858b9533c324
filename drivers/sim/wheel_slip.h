#pragma once

#include <random>

#include "drivers/sim/gauss_markov.h"

namespace mobot::sim {

struct WheelSlipOptions {
  // Standard deviation and correlation time of each wheel's ground-to-turned travel error.
  double noise_fraction = 0.0;
  double noise_correlation_s = 0.01;
  // The fastest a wheel's ground speed changes (m/s^2); 0: unlimited.
  double traction_accel_mps2 = 0.0;
};

// How far each wheel really rolls over the floor when it turns a given amount (docs/algorithms.md
// R2): its ground speed follows the turned speed within the traction limit (a hard start spins
// the wheel, a hard stop skids the base on), and the travel carries a random error. Speeds and
// travel are in the wheel's nominal metres (turned angle times nominal radius); the true radii
// apply afterwards.
class WheelSlip {
 public:
  struct Travel {
    double left_m = 0.0;
    double right_m = 0.0;
  };

  // Throws std::invalid_argument for negative or non-finite options or a zero correlation time.
  explicit WheelSlip(const WheelSlipOptions& options);

  // False when the floor adds nothing: ground travel is the turned travel, exactly.
  bool enabled() const;
  // Starts at rest with the noise in its stationary distribution.
  void reset(std::mt19937_64& rng);
  // The ground travel of a step of dt_s during which the wheels turn at these surface speeds.
  Travel step(double left_mps, double right_mps, double dt_s, std::mt19937_64& rng);
  // The base has been stopped by something: the wheels no longer slide.
  void stop();

 private:
  // Ground travel of one wheel over the step, updating its ground speed.
  double follow(double& ground_mps, double wheel_mps, double dt_s) const;

  WheelSlipOptions options_;
  GaussMarkov left_noise_;
  GaussMarkov right_noise_;
  double left_ground_mps_ = 0.0;
  double right_ground_mps_ = 0.0;
};

}  // namespace mobot::sim
