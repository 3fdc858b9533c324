#include "core/planning/turning_radius_fillet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace mobot::planning {
namespace {

// The largest curvature of the polyline, from the circle through each three consecutive points.
double max_curvature(const std::vector<geometry::Point2D>& p) {
  double worst = 0.0;
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    const double a = std::hypot(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y);
    const double b = std::hypot(p[i + 1].x - p[i].x, p[i + 1].y - p[i].y);
    const double c = std::hypot(p[i + 1].x - p[i - 1].x, p[i + 1].y - p[i - 1].y);
    const double cross = std::abs((p[i].x - p[i - 1].x) * (p[i + 1].y - p[i - 1].y) -
                                  (p[i].y - p[i - 1].y) * (p[i + 1].x - p[i - 1].x));
    worst = std::max(worst, 2.0 * cross / (a * b * c));
  }
  return worst;
}

TEST(TurningRadiusFillet, RoundsACornerToTheMinimumRadius) {
  const PlanningGrid grid(200, 200, 0.1, {});
  const std::vector<geometry::Point2D> corner{{1.0, 1.0}, {10.0, 1.0}, {10.0, 10.0}};
  TurningRadiusFilletOptions options;
  options.min_turning_radius_m = 2.0;
  options.arc_step_m = 0.1;
  const std::vector<geometry::Point2D> out = fillet_corners(grid, corner, options);
  EXPECT_GT(out.size(), 10u);
  EXPECT_EQ(out.front(), corner.front());
  EXPECT_EQ(out.back(), corner.back());
  EXPECT_LE(max_curvature(out), 1.0 / 2.0 + 1e-6);
  // The arc starts 2 m before the corner (tangent length R tan(45 deg)).
  EXPECT_NEAR(out[1].x, 8.0, 1e-9);
  EXPECT_NEAR(out[1].y, 1.0, 1e-9);
}

TEST(TurningRadiusFillet, ShortLegsGetASmallerRadius) {
  const PlanningGrid grid(200, 200, 0.1, {});
  // Legs of 1 m: a 2 m radius would need 2 m tangents; the corner uses what it can.
  const std::vector<geometry::Point2D> zigzag{{1, 1}, {2, 1}, {2, 2}, {3, 2}};
  TurningRadiusFilletOptions options;
  options.min_turning_radius_m = 2.0;
  const std::vector<geometry::Point2D> out = fillet_corners(grid, zigzag, options);
  EXPECT_GT(out.size(), zigzag.size());
  for (const auto& p : out) {
    EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y));
  }
}

TEST(TurningRadiusFillet, AnArcThroughAnObstacleLeavesTheCornerSharp) {
  PlanningGrid grid(200, 200, 0.1, {});
  // An obstacle inside the corner, where the arc would pass (around (9.4, 1.6)).
  for (int y = 12; y <= 20; ++y) {
    for (int x = 90; x <= 97; ++x) grid.set_cost({x, y}, PlanningGrid::kLethal);
  }
  const std::vector<geometry::Point2D> corner{{1.0, 0.5}, {10.0, 0.5}, {10.0, 10.0}};
  TurningRadiusFilletOptions options;
  options.min_turning_radius_m = 2.0;
  EXPECT_EQ(fillet_corners(grid, corner, options), corner);
}

TEST(TurningRadiusFillet, NoRadiusOrFewPointsChangeNothing) {
  const PlanningGrid grid(50, 50, 0.1, {});
  const std::vector<geometry::Point2D> corner{{1, 1}, {4, 1}, {4, 4}};
  EXPECT_EQ(fillet_corners(grid, corner, {}), corner);
  TurningRadiusFilletOptions options;
  options.min_turning_radius_m = 1.0;
  const std::vector<geometry::Point2D> two{{1, 1}, {4, 4}};
  EXPECT_EQ(fillet_corners(grid, two, options), two);
}

}  // namespace
}  // namespace mobot::planning
