#include "drivers/sim/sharp_ir_adc.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mobot::sim {
namespace {

SharpIrAdcOptions noiseless() {
  SharpIrAdcOptions options;
  options.noise_v = 0.0;
  options.gain_sigma = 0.0;
  options.spike_probability = 0.0;
  return options;
}

TEST(SharpIrAdc, NoiselessCountsInvertTheCurveWithinOneCount) {
  std::mt19937_64 rng(1);
  const SharpIrAdc adc(noiseless(), 1, rng);
  for (const double d_m : {0.10, 0.15, 0.3, 0.5, 0.79}) {
    const safety::SharpIrDistance read = adc.curve().distance_from_adc(adc.counts(0, d_m, rng));
    EXPECT_EQ(read.validity, safety::IrValidity::kValid) << d_m;
    EXPECT_NEAR(read.distance_m, d_m, 0.012 * d_m) << d_m;
  }
  // Nothing in front: the output floor, read as too far.
  EXPECT_EQ(adc.curve().distance_from_adc(adc.counts(0, std::nullopt, rng)).validity,
            safety::IrValidity::kTooFar);
  EXPECT_EQ(adc.counts(0, 5.0, rng), adc.counts(0, std::nullopt, rng));
}

TEST(SharpIrAdc, BelowThePeakTheOutputFoldsBack) {
  std::mt19937_64 rng(1);
  const SharpIrAdc adc(noiseless(), 1, rng);
  EXPECT_NEAR(adc.voltage_v(0, 0.07), 3.13, 0.01) << "the datasheet's peak";
  EXPECT_NEAR(adc.voltage_v(0, 0.035), adc.voltage_v(0, 0.07) / 2, 1e-12);
  EXPECT_DOUBLE_EQ(adc.voltage_v(0, 0.0), 0.0);
  // At 5.5 cm (a Dashgo touching a wall) the reading is still "too near"...
  EXPECT_EQ(adc.curve().distance_from_adc(adc.counts(0, 0.055, rng)).validity,
            safety::IrValidity::kTooNear);
  // ...but at 2 cm it reads as 32 cm: the ambiguity the validity window cannot catch.
  const safety::SharpIrDistance folded = adc.curve().distance_from_adc(adc.counts(0, 0.02, rng));
  EXPECT_EQ(folded.validity, safety::IrValidity::kValid);
  EXPECT_NEAR(folded.distance_m, 0.316, 0.01);
}

TEST(SharpIrAdc, ReadingNoiseGainsAndSpikes) {
  std::mt19937_64 rng(4);
  SharpIrAdcOptions options;
  options.spike_probability = 0.0;
  const SharpIrAdc adc(options, 10, rng);
  ASSERT_EQ(adc.sensors(), 10U);
  // Each unit its own gain around the curve.
  double gain_sum_sq = 0.0;
  const double nominal = adc.curve().voltage_at_distance_v(0.3);
  for (std::size_t i = 0; i < 10; ++i) {
    const double gain = adc.voltage_v(i, 0.3) / nominal;
    gain_sum_sq += (gain - 1.0) * (gain - 1.0);
  }
  EXPECT_GT(std::sqrt(gain_sum_sq / 10), 0.01);
  EXPECT_LT(std::sqrt(gain_sum_sq / 10), 0.06);
  // The reading noise in volts, seen through the 4.9 mV counts.
  double sum = 0.0;
  double sum_sq = 0.0;
  constexpr int kReads = 20000;
  for (int i = 0; i < kReads; ++i) {
    const double v = adc.curve().voltage_from_adc(adc.counts(0, 0.3, rng));
    sum += v;
    sum_sq += v * v;
  }
  const double mean = sum / kReads;
  EXPECT_NEAR(mean, adc.voltage_v(0, 0.3), 0.001);
  EXPECT_NEAR(std::sqrt(sum_sq / kReads - mean * mean), 0.02, 0.002);

  // Spikes read high (near), this often.
  options.noise_v = 0.0;
  options.spike_probability = 0.05;
  const SharpIrAdc spiky(options, 1, rng);
  const int calm = spiky.counts(0, 0.5, rng);
  int high = 0;
  for (int i = 0; i < kReads; ++i) {
    const int counts = spiky.counts(0, 0.5, rng);
    EXPECT_GE(counts, calm - 1);
    high += counts > calm + 1 ? 1 : 0;
  }
  EXPECT_NEAR(static_cast<double>(high) / kReads, 0.05 * (1.0 - 2.0 / 204.6 / 0.3), 0.005);
}

TEST(SharpIrAdc, RejectsBadOptions) {
  std::mt19937_64 rng(1);
  const auto make = [&rng](auto change) {
    SharpIrAdcOptions options;
    change(options);
    SharpIrAdc adc(options, 3, rng);
  };
  EXPECT_THROW(make([](auto& o) { o.noise_v = -0.01; }), std::invalid_argument);
  EXPECT_THROW(make([](auto& o) { o.spike_probability = 1.5; }), std::invalid_argument);
  EXPECT_THROW(make([](auto& o) { o.peak_distance_m = 0.0; }), std::invalid_argument);
  EXPECT_THROW(make([](auto& o) { o.far_distance_m = 0.05; }), std::invalid_argument);
  EXPECT_THROW(make([](auto& o) { o.curve.min_valid_m = 2.0; }), std::invalid_argument);
  EXPECT_NO_THROW(make([](auto&) {}));
}

}  // namespace
}  // namespace mobot::sim
