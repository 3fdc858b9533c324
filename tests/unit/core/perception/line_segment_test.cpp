#include "core/perception/line_segment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace mobot::perception {
namespace {

constexpr double kPi = std::numbers::pi;

LineSegment make_line(double rho, double alpha) {
  LineSegment line;
  line.rho_m = rho;
  line.alpha_rad = alpha;
  line.has_endpoints = false;
  return line;
}

TEST(LineSegment, NormalizedFlipsNegativeRho) {
  LineSegment line = make_line(-2.0, 0.3);
  line.cov_rho_alpha_m_rad = 0.01;
  const LineSegment n = normalized(line);
  EXPECT_NEAR(n.rho_m, 2.0, 1e-12);
  EXPECT_NEAR(n.alpha_rad, 0.3 - kPi, 1e-12);
  EXPECT_NEAR(n.cov_rho_alpha_m_rad, -0.01, 1e-15);
}

TEST(LineSegment, TransformKeepsPointsOnTheLine) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int trial = 0; trial < 50; ++trial) {
    const LineSegment line = normalized(make_line(u(rng), u(rng)));
    const geometry::Pose2D frame{u(rng), u(rng), u(rng)};
    // Two points on the line in the child frame stay on the transformed line in the parent.
    const double c = std::cos(line.alpha_rad);
    const double s = std::sin(line.alpha_rad);
    const geometry::Point2D foot{line.rho_m * c, line.rho_m * s};
    const geometry::Point2D along{foot.x - 2.0 * s, foot.y + 2.0 * c};
    const LineSegment out = transform_line(frame, line);
    EXPECT_GE(out.rho_m, 0.0);
    EXPECT_NEAR(signed_distance(out, geometry::transform_point(frame, foot)), 0.0, 1e-9);
    EXPECT_NEAR(signed_distance(out, geometry::transform_point(frame, along)), 0.0, 1e-9);
  }
}

TEST(LineSegment, TransformPropagatesCovarianceLikeFiniteDifferences) {
  LineSegment line = make_line(2.0, 0.4);
  line.var_rho_m2 = 1e-4;
  line.var_alpha_rad2 = 4e-4;
  line.cov_rho_alpha_m_rad = 5e-5;
  const geometry::Pose2D frame{0.3, -0.2, 0.5};
  const double h = 1e-7;
  const LineSegment base = transform_line(frame, line);
  LineSegment bumped = line;
  bumped.alpha_rad += h;
  const LineSegment moved = transform_line(frame, bumped);
  const double drho_dalpha = (moved.rho_m - base.rho_m) / h;
  const double expected_var = 1e-4 + 2 * drho_dalpha * 5e-5 + drho_dalpha * drho_dalpha * 4e-4;
  EXPECT_NEAR(base.var_rho_m2, expected_var, 1e-10);
  EXPECT_NEAR(base.cov_rho_alpha_m_rad, 5e-5 + drho_dalpha * 4e-4, 1e-10);
  EXPECT_NEAR(base.var_alpha_rad2, 4e-4, 1e-15);
}

TEST(LineSegment, ValidityRejectsNonFiniteAndNegativeRho) {
  EXPECT_TRUE(is_valid(make_line(1.0, 0.0)));
  EXPECT_FALSE(is_valid(make_line(-1.0, 0.0)));
  EXPECT_FALSE(is_valid(make_line(std::nan(""), 0.0)));
  LineSegment ends = make_line(1.0, 0.0);
  ends.has_endpoints = true;
  ends.end.x = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(is_valid(ends));
  LineSegment negative_var = make_line(1.0, 0.0);
  negative_var.var_rho_m2 = -1.0;
  EXPECT_FALSE(is_valid(negative_var));
}

}  // namespace
}  // namespace mobot::perception
