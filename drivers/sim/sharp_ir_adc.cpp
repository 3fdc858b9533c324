#include "drivers/sim/sharp_ir_adc.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mobot::sim {
namespace {

void check(const SharpIrAdcOptions& options) {
  for (const double value : {options.peak_distance_m, options.far_distance_m, options.noise_v,
                             options.gain_sigma, options.spike_probability, options.spike_max_v}) {
    if (!std::isfinite(value) || value < 0.0) {
      throw std::invalid_argument("sharp ir adc: distances, noise and spikes must be >= 0");
    }
  }
  if (options.spike_probability > 1.0 || !(options.peak_distance_m > 0.0) ||
      !(options.far_distance_m > options.peak_distance_m)) {
    throw std::invalid_argument(
        "sharp ir adc: the spike probability is at most 1 and 0 < peak < far distance");
  }
}

}  // namespace

SharpIrAdc::SharpIrAdc(const SharpIrAdcOptions& options, std::size_t sensors, std::mt19937_64& rng)
    : options_(options), curve_(options.curve) {
  check(options_);
  std::normal_distribution<double> gain(1.0, options_.gain_sigma);
  gains_.reserve(sensors);
  for (std::size_t i = 0; i < sensors; ++i) {
    gains_.push_back(options_.gain_sigma > 0.0 ? std::max(0.5, gain(rng)) : 1.0);
  }
}

double SharpIrAdc::voltage_v(std::size_t sensor, std::optional<double> distance_m) const {
  const double gain = sensor < gains_.size() ? gains_[sensor] : 1.0;
  const double far_m = options_.far_distance_m;
  const double d_m = distance_m ? std::clamp(*distance_m, 0.0, far_m) : far_m;
  if (d_m < options_.peak_distance_m) {
    return gain * curve_.voltage_at_distance_v(options_.peak_distance_m) * d_m /
           options_.peak_distance_m;
  }
  return gain * curve_.voltage_at_distance_v(d_m);
}

int SharpIrAdc::counts(std::size_t sensor, std::optional<double> distance_m,
                       std::mt19937_64& rng) const {
  double voltage = voltage_v(sensor, distance_m);
  if (options_.noise_v > 0.0)
    voltage += std::normal_distribution<double>(0.0, options_.noise_v)(rng);
  if (options_.spike_probability > 0.0 &&
      std::uniform_real_distribution<double>(0.0, 1.0)(rng) < options_.spike_probability) {
    voltage += std::uniform_real_distribution<double>(0.0, options_.spike_max_v)(rng);
  }
  return curve_.adc_from_voltage(voltage);
}

}  // namespace mobot::sim
