#include "core/estimation/line_measurement_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace mobot::estimation {
namespace {

constexpr double kPi = std::numbers::pi;

perception::LineSegment line(double rho, double alpha) {
  perception::LineSegment l;
  l.rho_m = rho;
  l.alpha_rad = alpha;
  l.has_endpoints = false;
  return l;
}

// Central differences of z w.r.t. the pose; the angle row is differenced through wrap_angle.
Eigen::Matrix<double, 2, 3> numeric_jacobian(const geometry::Pose2D& pose,
                                             const perception::LineSegment& map_line,
                                             double observed_alpha) {
  const double h = 1e-6;
  Eigen::Matrix<double, 2, 3> j;
  for (int i = 0; i < 3; ++i) {
    geometry::Pose2D plus = pose;
    geometry::Pose2D minus = pose;
    double* p = i == 0 ? &plus.x : i == 1 ? &plus.y : &plus.theta;
    double* m = i == 0 ? &minus.x : i == 1 ? &minus.y : &minus.theta;
    *p += h;
    *m -= h;
    const auto zp = predict_line_measurement(plus, map_line, observed_alpha).z;
    const auto zm = predict_line_measurement(minus, map_line, observed_alpha).z;
    j(0, i) = (zp(0) - zm(0)) / (2 * h);
    j(1, i) = geometry::wrap_angle(zp(1) - zm(1)) / (2 * h);
  }
  return j;
}

TEST(LineMeasurementModel, MatchesE2Formulas) {
  // Wall x = 4 seen from (1, 2, 0.3): C = 3, r = 3, psi = -0.3.
  auto p = predict_line_measurement({1.0, 2.0, 0.3}, line(4.0, 0.0));
  EXPECT_NEAR(p.z(0), 3.0, 1e-12);
  EXPECT_NEAR(p.z(1), -0.3, 1e-12);
  EXPECT_NEAR(p.h(0, 0), -1.0, 1e-12);
  EXPECT_NEAR(p.h(1, 2), -1.0, 1e-12);
  // From beyond the wall, (5, 2, 0.3): C = -1, r = 1, psi = -0.3 + pi.
  p = predict_line_measurement({5.0, 2.0, 0.3}, line(4.0, 0.0));
  EXPECT_NEAR(p.z(0), 1.0, 1e-12);
  EXPECT_NEAR(p.z(1), kPi - 0.3, 1e-12);
  EXPECT_NEAR(p.h(0, 0), 1.0, 1e-12);
}

TEST(LineMeasurementModel, HintPicksTheEquivalentFormNearTheObservation) {
  // The estimate has crossed the wall, but the robot sees it ahead (alpha near -0.3): the
  // prediction becomes (-1, -0.3) instead of (1, pi - 0.3), so the innovation stays small.
  const auto p = predict_line_measurement({5.0, 2.0, 0.3}, line(4.0, 0.0), -0.3);
  EXPECT_NEAR(p.z(0), -1.0, 1e-12);
  EXPECT_NEAR(p.z(1), -0.3, 1e-12);
  EXPECT_NEAR(p.h(0, 0), -1.0, 1e-12);
}

TEST(LineMeasurementModel, JacobianMatchesFiniteDifferences) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> pos(-5.0, 5.0);
  std::uniform_real_distribution<double> ang(-kPi, kPi);
  std::uniform_real_distribution<double> rho(0.0, 6.0);
  const double near_wrap[] = {kPi - 1e-4, -kPi + 1e-4, kPi, 0.0};
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    geometry::Pose2D pose{pos(rng), pos(rng), trial % 4 == 0 ? near_wrap[trial / 4 % 4] : ang(rng)};
    // Lines whose normal is near +-pi too, so psi wraps.
    const auto map_line = line(rho(rng), trial % 3 == 0 ? kPi - 1e-5 : ang(rng));
    const auto p = predict_line_measurement(pose, map_line);
    if (p.z(0) < 1e-3) continue;  // r = |C| has a kink on the line itself
    const double hint = ang(rng);
    const auto hinted = predict_line_measurement(pose, map_line, hint);
    EXPECT_TRUE(p.h.isApprox(numeric_jacobian(pose, map_line, p.z(1)), 1e-6)) << trial;
    EXPECT_TRUE(hinted.h.isApprox(numeric_jacobian(pose, map_line, hint), 1e-6)) << trial;
    ++checked;
  }
  EXPECT_GT(checked, 350);
}

TEST(LineMeasurementModel, InnovationWrapsTheAngle) {
  LineMeasurementPrediction p;
  p.z << 2.0, -kPi + 0.01;
  perception::LineSegment observed = line(2.1, kPi - 0.01);
  const Eigen::Vector2d nu = line_innovation(observed, p);
  EXPECT_NEAR(nu(0), 0.1, 1e-12);
  EXPECT_NEAR(nu(1), -0.02, 1e-12);
}

}  // namespace
}  // namespace mobot::estimation
