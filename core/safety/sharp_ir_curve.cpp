#include "core/safety/sharp_ir_curve.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/numeric/finite.h"

namespace mobot::safety {
namespace {

constexpr double kCentimetresPerMetre = 100.0;

}  // namespace

SharpIrCurve::SharpIrCurve(const SharpIrCurveOptions& options) : options_(options) {
  if (!finite_positive(options.reference_voltage_v) || options.adc_full_scale <= 0 ||
      !finite_positive(options.coefficient_cm) || !finite_positive(options.exponent) ||
      !finite_positive(options.min_valid_m) || !finite_positive(options.max_valid_m) ||
      !(options.min_valid_m < options.max_valid_m)) {
    throw std::invalid_argument(
        "sharp ir curve: reference, full scale, coefficient, exponent and the window must be "
        "positive, with min_valid_m < max_valid_m");
  }
}

double SharpIrCurve::voltage_from_adc(int adc) const {
  return adc * options_.reference_voltage_v / options_.adc_full_scale;
}

double SharpIrCurve::distance_from_voltage_m(double voltage_v) const {
  if (std::isnan(voltage_v)) return std::numeric_limits<double>::quiet_NaN();
  if (voltage_v <= 0.0) return std::numeric_limits<double>::infinity();
  return options_.coefficient_cm * std::pow(voltage_v, -options_.exponent) / kCentimetresPerMetre;
}

double SharpIrCurve::voltage_at_distance_v(double distance_m) const {
  if (!(distance_m > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  if (std::isinf(distance_m)) return 0.0;
  return std::pow(options_.coefficient_cm / (distance_m * kCentimetresPerMetre),
                  1.0 / options_.exponent);
}

int SharpIrCurve::adc_from_voltage(double voltage_v) const {
  if (std::isnan(voltage_v)) return 0;
  const double counts = voltage_v * options_.adc_full_scale / options_.reference_voltage_v;
  return static_cast<int>(
      std::lround(std::clamp(counts, 0.0, static_cast<double>(options_.adc_full_scale))));
}

SharpIrDistance SharpIrCurve::distance_from_adc(int adc) const {
  if (adc < 0 || adc > options_.adc_full_scale) {
    return {std::numeric_limits<double>::quiet_NaN(), IrValidity::kBadCount};
  }
  const double distance_m = distance_from_voltage_m(voltage_from_adc(adc));
  if (distance_m < options_.min_valid_m) return {distance_m, IrValidity::kTooNear};
  if (distance_m > options_.max_valid_m) return {distance_m, IrValidity::kTooFar};
  return {distance_m, IrValidity::kValid};
}

double SharpIrCurve::ring_range_m(int adc) const {
  const SharpIrDistance distance = distance_from_adc(adc);
  switch (distance.validity) {
    case IrValidity::kValid:
      return distance.distance_m;
    case IrValidity::kTooNear:
      return options_.min_valid_m;
    case IrValidity::kTooFar:
      return options_.max_valid_m;
    case IrValidity::kBadCount:
      break;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

msgs::RangeReading SharpIrCurve::reading(int adc, const geometry::Pose2D& sensor_in_base,
                                         double cone_rad) const {
  return {sensor_in_base, cone_rad, options_.min_valid_m, options_.max_valid_m, ring_range_m(adc)};
}

}  // namespace mobot::safety
