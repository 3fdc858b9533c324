#include "core/perception/line_fitter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace mobot::perception {
namespace {

TEST(LineFitter, FitsExactLineInHessianForm) {
  // x cos(a) + y sin(a) = 3 with a = 2.5 rad.
  const double alpha = 2.5;
  const double rho = 3.0;
  LineFitter fitter;
  for (int i = -5; i <= 5; ++i) {
    const double t = 0.3 * i;
    fitter.add(
        {rho * std::cos(alpha) - t * std::sin(alpha), rho * std::sin(alpha) + t * std::cos(alpha)});
  }
  const LineSegment line = fitter.fit();
  EXPECT_NEAR(line.rho_m, rho, 1e-9);
  EXPECT_NEAR(line.alpha_rad, alpha, 1e-9);
  EXPECT_EQ(line.point_count, 11);
}

TEST(LineFitter, FarAwayPointsKeepPrecision) {
  LineFitter fitter;
  for (int i = 0; i < 100; ++i) fitter.add({1000.0 + 0.01 * i, 500.0});
  const LineSegment line = fitter.fit();
  EXPECT_NEAR(line.rho_m, 500.0, 1e-6);
  EXPECT_NEAR(line.alpha_rad, std::numbers::pi / 2, 1e-9);
}

// The claimed covariance must agree with the scatter of fits over many noisy draws.
TEST(LineFitter, CovarianceMatchesMonteCarlo) {
  const double sigma = 0.02;
  const double rho = 2.0;
  const double alpha = 0.3;
  // Unequal point errors (as range noise seen at varying incidence): the claim must be that of
  // the unweighted fit actually used.
  auto point_sigma = [sigma](int i) { return sigma * (0.2 + 0.1 * i); };
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<double> rhos;
  std::vector<double> alphas;
  LineSegment claimed;
  for (int trial = 0; trial < 2000; ++trial) {
    LineFitter fitter;
    std::vector<geometry::Point2D> points;
    for (int i = 0; i < 30; ++i) {
      const double t = -1.0 + 0.05 * i;  // asymmetric about the foot point: couples rho, alpha
      const double d = noise(rng) * point_sigma(i) / sigma;
      points.push_back({(rho + d) * std::cos(alpha) - t * std::sin(alpha),
                        (rho + d) * std::sin(alpha) + t * std::cos(alpha)});
      fitter.add(points.back());
    }
    const LineSegment fit = fitter.fit();
    rhos.push_back(fit.rho_m);
    alphas.push_back(fit.alpha_rad);
  }
  // The analytic claim, from noise-free points so that no scatter inflation enters.
  {
    LineFitter fitter;
    std::vector<geometry::Point2D> points;
    for (int i = 0; i < 30; ++i) {
      const double t = -1.0 + 0.05 * i;
      points.push_back({rho * std::cos(alpha) - t * std::sin(alpha),
                        rho * std::sin(alpha) + t * std::cos(alpha)});
      fitter.add(points.back());
    }
    std::vector<double> var;
    for (int i = 0; i < 30; ++i) var.push_back(point_sigma(i) * point_sigma(i));
    claimed = with_covariance(fitter.fit(), points, var);
  }
  auto moments = [](const std::vector<double>& a, const std::vector<double>& b) {
    double ma = 0, mb = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      ma += a[i];
      mb += b[i];
    }
    ma /= a.size();
    mb /= b.size();
    double c = 0;
    for (std::size_t i = 0; i < a.size(); ++i) c += (a[i] - ma) * (b[i] - mb);
    return c / (a.size() - 1);
  };
  EXPECT_NEAR(moments(rhos, rhos) / claimed.var_rho_m2, 1.0, 0.1);
  EXPECT_NEAR(moments(alphas, alphas) / claimed.var_alpha_rad2, 1.0, 0.1);
  EXPECT_NEAR(moments(rhos, alphas) / claimed.cov_rho_alpha_m_rad, 1.0, 0.15);
}

TEST(LineFitter, RoughWallInflatesCovariance) {
  std::vector<geometry::Point2D> points;
  LineFitter fitter;
  for (int i = 0; i < 20; ++i) {
    points.push_back({0.1 * i, 1.0 + ((i % 2) != 0 ? 0.05 : -0.05)});
    fitter.add(points.back());
  }
  const std::vector<double> tiny(points.size(), 1e-6);
  const LineSegment line = with_covariance(fitter.fit(), points, tiny);
  // Without inflation var(rho) would be about 1e-6 / 20.
  EXPECT_GT(line.var_rho_m2, 1e-4);
}

TEST(LineFitter, DegeneratePointsLeaveCovarianceUnset) {
  std::vector<geometry::Point2D> points(5, {1.0, 1.0});
  LineFitter fitter;
  for (const auto& p : points) fitter.add(p);
  const std::vector<double> var(points.size(), 1e-4);
  const LineSegment line = with_covariance(fitter.fit(), points, var);
  EXPECT_EQ(line.var_rho_m2, 0.0);
  EXPECT_EQ(line.var_alpha_rad2, 0.0);
}

}  // namespace
}  // namespace mobot::perception
