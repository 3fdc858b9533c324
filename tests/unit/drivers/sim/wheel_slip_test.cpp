#include "drivers/sim/wheel_slip.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mobot::sim {
namespace {

constexpr double kDt_s = 0.02;

// Ground travel of the left wheel over `duration_s` at a constant turned speed.
double roll(WheelSlip& slip, double wheel_mps, double duration_s, std::mt19937_64& rng) {
  double travel_m = 0.0;
  for (double t = 0.0; t < duration_s - 1e-9; t += kDt_s) {
    travel_m += slip.step(wheel_mps, wheel_mps, kDt_s, rng).left_m;
  }
  return travel_m;
}

TEST(WheelSlip, WithoutSlipTheGroundTravelIsTheTurnedTravel) {
  std::mt19937_64 rng(1);
  WheelSlip none({});
  EXPECT_FALSE(none.enabled());
  none.reset(rng);
  const WheelSlip::Travel travel = none.step(0.4, -0.2, kDt_s, rng);
  EXPECT_DOUBLE_EQ(travel.left_m, 0.4 * kDt_s);
  EXPECT_DOUBLE_EQ(travel.right_m, -0.2 * kDt_s);
}

TEST(WheelSlip, AHardStartSpinsAndAHardStopSlides) {
  std::mt19937_64 rng(1);
  WheelSlip slip({0.0, 0.01, 3.0});
  ASSERT_TRUE(slip.enabled());
  slip.reset(rng);
  // 0 -> 0.5 m/s at once: the ground takes 1/6 s to catch up, losing v^2 / 2a = 4.2 cm.
  EXPECT_NEAR(roll(slip, 0.5, 1.0, rng), 0.5 - 0.25 / 6.0, 1e-9);
  // 0.5 -> 0 at once: the base slides on by the same.
  EXPECT_NEAR(roll(slip, 0.0, 1.0, rng), 0.25 / 6.0, 1e-9);
  EXPECT_NEAR(roll(slip, 0.0, 1.0, rng), 0.0, 1e-12);
  // Reversing from +0.5 to -0.5: the ground passes through zero at 3 m/s^2.
  roll(slip, 0.5, 1.0, rng);
  EXPECT_NEAR(roll(slip, -0.5, 1.0, rng), -0.5 + 1.0 / 6.0, 1e-9);
  // Something stopped the base: no slide after it.
  roll(slip, 0.5, 1.0, rng);
  slip.stop();
  EXPECT_NEAR(roll(slip, 0.0, 1.0, rng), 0.0, 1e-12);
}

TEST(WheelSlip, TheTravelNoiseHasTheConfiguredSize) {
  // 3 % with a 10 ms correlation: over T the travel error's variance is about 2 s^2 tau T v^2.
  std::mt19937_64 rng(5);
  constexpr int kRuns = 2000;
  constexpr double kSpeed_mps = 0.3;
  constexpr double kDuration_s = 10.0;
  double sum = 0.0;
  double sum_sq = 0.0;
  for (int run = 0; run < kRuns; ++run) {
    WheelSlip slip({0.03, 0.01, 0.0});
    slip.reset(rng);
    const double error_m = roll(slip, kSpeed_mps, kDuration_s, rng) - kSpeed_mps * kDuration_s;
    sum += error_m;
    sum_sq += error_m * error_m;
  }
  const double mean = sum / kRuns;
  const double sigma = std::sqrt(sum_sq / kRuns - mean * mean);
  const double expected = kSpeed_mps * std::sqrt(2 * 0.03 * 0.03 * 0.01 * kDuration_s);
  EXPECT_NEAR(mean, 0.0, 4 * expected / std::sqrt(kRuns));
  EXPECT_NEAR(sigma / expected, 1.0, 0.08);
}

TEST(WheelSlip, RejectsBadOptions) {
  EXPECT_THROW(WheelSlip({-0.1, 0.01, 0.0}), std::invalid_argument);
  EXPECT_THROW(WheelSlip({0.03, 0.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(WheelSlip({0.03, 0.01, -1.0}), std::invalid_argument);
  EXPECT_THROW(WheelSlip({0.03, 0.01, std::nan("")}), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::sim
