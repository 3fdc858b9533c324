#pragma once

#include <cstddef>
#include <optional>
#include <random>
#include <vector>

#include "core/safety/sharp_ir_curve.h"

namespace mobot::sim {

// What a Sharp GP2Y0A21 and the Arduino's 10-bit converter make of a true distance
// (docs/algorithms.md R2): the calibration curve inverted, a gain error of its own per unit, the
// fold-back below the peak, reading noise, the odd spike, and quantisation.
struct SharpIrAdcOptions {
  safety::SharpIrCurveOptions curve;
  // Nearer than this the output falls again, linearly to 0 V at contact: the datasheet's peak of
  // about 3.1 V at 6-7 cm (the curve gives 3.13 V at 7 cm). A near object then reads far.
  double peak_distance_m = 0.07;
  // Beyond this nothing returns that the detector tells from its own floor: the output stays at
  // the curve's value here (0.25 V), a reading of "too far".
  double far_distance_m = 1.5;
  // Per reading, after the Arduino's averaging: about +/- 1 cm at 20 cm, +/- 4 cm at 70 cm,
  // where the curve flattens.
  double noise_v = 0.02;
  // Unit-to-unit spread of the output around the calibrated curve, one draw per sensor and seed
  // (the datasheet allows 0.25-0.55 V at 80 cm; a calibrated ring is much closer than that).
  double gain_sigma = 0.03;
  // A sample taken during the LED's pulse reads high (near); after averaging a reading is off
  // by up to spike_max_v, this often.
  double spike_probability = 0.01;
  double spike_max_v = 0.3;
};

class SharpIrAdc {
 public:
  // Draws each sensor's gain from `rng`. Throws std::invalid_argument for negative or non-finite
  // options or a probability above 1.
  SharpIrAdc(const SharpIrAdcOptions& options, std::size_t sensors, std::mt19937_64& rng);

  // Sensor `sensor`'s output without noise for an object at `distance_m` (nothing: no object
  // within far_distance_m).
  double voltage_v(std::size_t sensor, std::optional<double> distance_m) const;
  // One reading as the Arduino reports it.
  int counts(std::size_t sensor, std::optional<double> distance_m, std::mt19937_64& rng) const;

  std::size_t sensors() const { return gains_.size(); }
  const safety::SharpIrCurve& curve() const { return curve_; }

 private:
  SharpIrAdcOptions options_;
  safety::SharpIrCurve curve_;
  std::vector<double> gains_;  // multiplies the output
};

}  // namespace mobot::sim
