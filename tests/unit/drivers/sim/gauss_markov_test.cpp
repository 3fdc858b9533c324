#include "drivers/sim/gauss_markov.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace mobot::sim {
namespace {

// Variance of the integral over T of a stationary process: 2 s^2 tau^2 (T/tau - 1 + e^(-T/tau)).
double integral_variance(double sigma, double tau_s, double duration_s) {
  const double h = duration_s / tau_s;
  return 2.0 * sigma * sigma * tau_s * tau_s * (h - 1.0 + std::exp(-h));
}

// The integral over `duration_s` in steps of dt_s, summed from the step means, over many runs.
double measured_integral_variance(double sigma, double tau_s, double dt_s, double duration_s,
                                  int runs, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  double sum = 0.0;
  double sum_sq = 0.0;
  const int steps = static_cast<int>(std::lround(duration_s / dt_s));
  for (int run = 0; run < runs; ++run) {
    GaussMarkov process(sigma, tau_s);
    process.start(rng);
    double integral = 0.0;
    for (int i = 0; i < steps; ++i) integral += process.advance(dt_s, rng) * dt_s;
    sum += integral;
    sum_sq += integral * integral;
  }
  const double mean = sum / runs;
  return sum_sq / runs - mean * mean;
}

TEST(GaussMarkov, TheAccumulatedErrorDoesNotDependOnTheStep) {
  // tau = 10 ms: shorter than most steps, where a per-step draw of the state would be wrong by
  // orders of magnitude.
  constexpr double kSigma = 0.03;
  constexpr double kTau_s = 0.01;
  constexpr double kDuration_s = 2.0;
  const double expected = integral_variance(kSigma, kTau_s, kDuration_s);
  for (const double dt_s : {0.001, 0.005, 0.02, 0.2, 1.0}) {
    const double measured = measured_integral_variance(kSigma, kTau_s, dt_s, kDuration_s, 4000, 7);
    EXPECT_NEAR(measured / expected, 1.0, 0.08) << "dt " << dt_s;
  }
  // Long correlation (the short steps take the series branch of the variance).
  const double slow = integral_variance(0.02, 0.5, 3.0);
  for (const double dt_s : {0.002, 0.02, 0.5}) {
    EXPECT_NEAR(measured_integral_variance(0.02, 0.5, dt_s, 3.0, 4000, 11) / slow, 1.0, 0.08)
        << "dt " << dt_s;
  }
}

TEST(GaussMarkov, StartsStationaryAndStaysSo) {
  std::mt19937_64 rng(3);
  double sum_sq = 0.0;
  constexpr int kRuns = 20000;
  for (int run = 0; run < kRuns; ++run) {
    GaussMarkov process(0.05, 0.1);
    process.start(rng);
    process.advance(0.37, rng);
    sum_sq += process.value() * process.value();
  }
  EXPECT_NEAR(std::sqrt(sum_sq / kRuns), 0.05, 0.002);
}

TEST(GaussMarkov, EdgesAndBadArguments) {
  std::mt19937_64 rng(1);
  GaussMarkov silent(0.0, 0.1);
  silent.start(rng);
  EXPECT_EQ(silent.advance(0.02, rng), 0.0);
  GaussMarkov process(0.1, 0.1);
  process.start(rng);
  const double x = process.value();
  EXPECT_EQ(process.advance(0.0, rng), x) << "no time, no change";
  EXPECT_EQ(process.advance(-1.0, rng), x);
  EXPECT_EQ(process.advance(std::nan(""), rng), x);
  EXPECT_THROW(GaussMarkov(-0.1, 0.1), std::invalid_argument);
  EXPECT_THROW(GaussMarkov(0.1, 0.0), std::invalid_argument);
  EXPECT_THROW(GaussMarkov(0.1, std::numeric_limits<double>::infinity()), std::invalid_argument);
  EXPECT_THROW(GaussMarkov(std::nan(""), 0.1), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::sim
