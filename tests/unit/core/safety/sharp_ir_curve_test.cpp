#include "core/safety/sharp_ir_curve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace mobot::safety {
namespace {

TEST(SharpIrCurve, ConvertsCountsWithTheDashgoCurve) {
  const SharpIrCurve curve;
  // V = 400 * 5 / 1023 = 1.955 V, D = 27.728 * 1.955^-1.2045 cm = 12.40 cm.
  EXPECT_NEAR(curve.voltage_from_adc(400), 1.95503, 1e-5);
  const SharpIrDistance distance = curve.distance_from_adc(400);
  EXPECT_EQ(distance.validity, IrValidity::kValid);
  EXPECT_NEAR(distance.distance_m, 0.27728 * std::pow(2000.0 / 1023.0, -1.2045), 1e-12);
  EXPECT_NEAR(distance.distance_m, 0.1240, 5e-4);
}

TEST(SharpIrCurve, TheInverseCurveRoundTrips) {
  const SharpIrCurve curve;
  for (const double d_m : {0.10, 0.2, 0.35, 0.5, 0.8}) {
    const double voltage = curve.voltage_at_distance_v(d_m);
    EXPECT_NEAR(curve.distance_from_voltage_m(voltage), d_m, 1e-12) << d_m;
    // Quantised to one count (4.9 mV) the distance moves by less than the curve's slope allows:
    // 0.3 mm at 10 cm, 9 mm at 80 cm.
    const SharpIrDistance read = curve.distance_from_adc(curve.adc_from_voltage(voltage));
    EXPECT_NEAR(read.distance_m, d_m, 0.012 * d_m) << d_m;
  }
  // The datasheet's corners: about 2.3 V at 10 cm and 0.4 V at 80 cm.
  EXPECT_NEAR(curve.voltage_at_distance_v(0.10), 2.33, 0.01);
  EXPECT_NEAR(curve.voltage_at_distance_v(0.80), 0.415, 0.005);
}

TEST(SharpIrCurve, TheValidityWindowIsTenToEightyCentimetres) {
  const SharpIrCurve curve;
  const int at_10cm = curve.adc_from_voltage(curve.voltage_at_distance_v(0.10));
  const int at_80cm = curve.adc_from_voltage(curve.voltage_at_distance_v(0.80));
  // More volts is nearer: one count above the 10 cm count is too near.
  EXPECT_EQ(curve.distance_from_adc(at_10cm + 2).validity, IrValidity::kTooNear);
  EXPECT_EQ(curve.distance_from_adc(at_10cm - 1).validity, IrValidity::kValid);
  EXPECT_EQ(curve.distance_from_adc(at_80cm + 1).validity, IrValidity::kValid);
  EXPECT_EQ(curve.distance_from_adc(at_80cm - 2).validity, IrValidity::kTooFar);
  EXPECT_EQ(curve.distance_from_adc(1023).validity, IrValidity::kTooNear);
  // No light at all: 0 V is infinitely far, which is too far, not an error.
  const SharpIrDistance dark = curve.distance_from_adc(0);
  EXPECT_EQ(dark.validity, IrValidity::kTooFar);
  EXPECT_TRUE(std::isinf(dark.distance_m));
}

TEST(SharpIrCurve, CountsTheConverterCannotProduceAreBad) {
  const SharpIrCurve curve;
  for (const int adc : {-1, 1024, 65535}) {
    const SharpIrDistance distance = curve.distance_from_adc(adc);
    EXPECT_EQ(distance.validity, IrValidity::kBadCount) << adc;
    EXPECT_TRUE(std::isnan(distance.distance_m)) << adc;
    EXPECT_TRUE(std::isnan(curve.ring_range_m(adc))) << adc;
  }
}

TEST(SharpIrCurve, TheRingRangeClampsToTheWindow) {
  const SharpIrCurve curve;
  EXPECT_DOUBLE_EQ(curve.ring_range_m(1000), 0.10) << "too near: something is within 10 cm";
  EXPECT_DOUBLE_EQ(curve.ring_range_m(20), 0.80) << "too far: nothing in range";
  EXPECT_DOUBLE_EQ(curve.ring_range_m(0), 0.80);
  EXPECT_NEAR(curve.ring_range_m(400), 0.1240, 5e-4);
  const msgs::RangeReading reading = curve.reading(400, {0.145, 0.0, 0.0}, 0.1);
  EXPECT_EQ(reading.sensor_in_base, (geometry::Pose2D{0.145, 0.0, 0.0}));
  EXPECT_DOUBLE_EQ(reading.cone_rad, 0.1);
  EXPECT_DOUBLE_EQ(reading.range_min_m, 0.10);
  EXPECT_DOUBLE_EQ(reading.range_max_m, 0.80);
  EXPECT_DOUBLE_EQ(reading.range_m, curve.ring_range_m(400));
}

TEST(SharpIrCurve, EdgesOfTheVoltageAndDistanceFunctions) {
  const SharpIrCurve curve;
  EXPECT_TRUE(std::isinf(curve.distance_from_voltage_m(0.0)));
  EXPECT_TRUE(std::isinf(curve.distance_from_voltage_m(-1.0)));
  EXPECT_TRUE(std::isnan(curve.distance_from_voltage_m(std::nan(""))));
  EXPECT_TRUE(std::isnan(curve.voltage_at_distance_v(0.0)));
  EXPECT_TRUE(std::isnan(curve.voltage_at_distance_v(-0.1)));
  EXPECT_TRUE(std::isnan(curve.voltage_at_distance_v(std::nan(""))));
  EXPECT_DOUBLE_EQ(curve.voltage_at_distance_v(std::numeric_limits<double>::infinity()), 0.0);
  EXPECT_EQ(curve.adc_from_voltage(-0.5), 0);
  EXPECT_EQ(curve.adc_from_voltage(7.0), 1023);
  EXPECT_EQ(curve.adc_from_voltage(std::nan("")), 0);
  EXPECT_EQ(curve.adc_from_voltage(2.5), 512);  // 511.5 rounds up
}

TEST(SharpIrCurve, RejectsOptionsThatMakeNoCurve) {
  const auto rejects = [](auto change) {
    SharpIrCurveOptions options;
    change(options);
    return [options] { SharpIrCurve curve(options); };
  };
  EXPECT_THROW(rejects([](auto& o) { o.reference_voltage_v = 0.0; })(), std::invalid_argument);
  EXPECT_THROW(rejects([](auto& o) { o.adc_full_scale = 0; })(), std::invalid_argument);
  EXPECT_THROW(rejects([](auto& o) { o.exponent = std::nan(""); })(), std::invalid_argument);
  EXPECT_THROW(rejects([](auto& o) { o.coefficient_cm = -1.0; })(), std::invalid_argument);
  EXPECT_THROW(rejects([](auto& o) { o.min_valid_m = 0.9; })(), std::invalid_argument);
  EXPECT_NO_THROW(rejects([](auto&) {})());
}

}  // namespace
}  // namespace mobot::safety
