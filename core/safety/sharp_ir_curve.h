#pragma once

#include "core/geometry/pose2d.h"
#include "core/msgs/sonar_ring.h"

namespace mobot::safety {

// The Dashgo's calibration of its Sharp GP2Y0A21 infrared rangers (docs/algorithms.md R2), as its
// Arduino Mega reads them: V = ADC * reference / full_scale, D[cm] = coefficient * V^-exponent,
// trusted only inside [min_valid_m, max_valid_m].
struct SharpIrCurveOptions {
  double reference_voltage_v = 5.0;  // the Mega's ADC reference
  int adc_full_scale = 1023;         // 10-bit converter: V = ADC * 5.0 / 1023
  double coefficient_cm = 27.728;
  double exponent = 1.2045;
  // The sensor's datasheet window. Nearer than 10 cm its output folds back (the voltage falls
  // again), so a near object can read as a far one; beyond 80 cm the curve is flat in the noise.
  double min_valid_m = 0.10;
  double max_valid_m = 0.80;
};

enum class IrValidity {
  kValid,
  kTooNear,  // the curve gives less than min_valid_m: something is at most that close
  kTooFar,   // more than max_valid_m, or no light returned (0 V)
  kBadCount  // outside [0, adc_full_scale]: not something the converter can produce
};

struct SharpIrDistance {
  double distance_m = 0.0;  // the curve's answer (+infinity at 0 V; NaN for a bad count)
  IrValidity validity = IrValidity::kBadCount;
};

class SharpIrCurve {
 public:
  // Throws std::invalid_argument unless every number is finite and positive and
  // 0 < min_valid_m < max_valid_m.
  explicit SharpIrCurve(const SharpIrCurveOptions& options = {});

  const SharpIrCurveOptions& options() const { return options_; }

  double voltage_from_adc(int adc) const;
  // +infinity for v <= 0 (nothing returned), NaN for NaN.
  double distance_from_voltage_m(double voltage_v) const;
  // The inverse: what the curve says a sensor outputs at this distance (> 0). The simulator
  // produces counts with it.
  double voltage_at_distance_v(double distance_m) const;
  // The converter's count for a voltage: rounded to the nearest step, clamped to [0, full scale].
  int adc_from_voltage(double voltage_v) const;

  SharpIrDistance distance_from_adc(int adc) const;

  // The range a msgs::RangeReading carries for this count: the distance inside the window,
  // min_valid_m when too near (the object is at most that far: safety must see it), max_valid_m
  // when too far (nothing in range, the ring's "no echo"), NaN for a bad count.
  double ring_range_m(int adc) const;
  // One sensor of the ring: its mount, beam width and window, and ring_range_m(adc).
  msgs::RangeReading reading(int adc, const geometry::Pose2D& sensor_in_base,
                             double cone_rad) const;

 private:
  SharpIrCurveOptions options_;
};

}  // namespace mobot::safety
