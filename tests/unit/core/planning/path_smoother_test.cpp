#include "core/planning/path_smoother.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/mapping/occupancy_grid.h"
#include "core/planning/astar_planner.h"
#include "core/planning/line_of_sight.h"
#include "core/planning/planning_grid_builder.h"

namespace mobot::planning {
namespace {

using mapping::OccupancyGrid;

double length(const std::vector<geometry::Point2D>& points) {
  double total = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) {
    total += std::hypot(points[i].x - points[i - 1].x, points[i].y - points[i - 1].y);
  }
  return total;
}

// 8 x 6 m at 0.05 m: outer walls, an inner wall with a 1.2 m door, and a pillar.
PlanningGrid office() {
  OccupancyGrid map(160, 120, 0.05, {}, OccupancyGrid::kFree);
  const auto wall = [&](int x0, int y0, int x1, int y1) {
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) map.set({x, y}, OccupancyGrid::kOccupied);
    }
  };
  wall(0, 0, 159, 1);
  wall(0, 118, 159, 119);
  wall(0, 0, 1, 119);
  wall(158, 0, 159, 119);
  wall(80, 0, 81, 70);  // door from y = 71 to 94 (1.2 m)
  wall(80, 95, 81, 119);
  wall(30, 40, 45, 55);  // pillar
  return PlanningGridBuilder().build(map);
}

struct Fixture {
  PlanningGrid grid = office();
  PlanResult plan;
  Fixture() {
    AStarPlanner planner;
    plan = planner.plan(grid, {0.6, 0.6, 0.0}, {7.3, 0.7, 0.0});
  }
};

TEST(PathSmoother, ShortcutsKeepClearanceAndShortenThePath) {
  const Fixture f;
  ASSERT_TRUE(f.plan.ok());
  PathSmootherOptions options;
  options.waypoint_spacing_m = 0.0;
  const PathSmoother smoother(options);
  const std::vector<geometry::Point2D> smooth = smoother.smooth(f.grid, f.plan.points_in_map);
  ASSERT_GE(smooth.size(), 2U);
  EXPECT_LT(smooth.size(), f.plan.points_in_map.size() / 5);
  EXPECT_EQ(smooth.front(), f.plan.points_in_map.front());
  EXPECT_EQ(smooth.back(), f.plan.points_in_map.back());
  EXPECT_LT(length(smooth), f.plan.length_m - 0.2);
  for (std::size_t i = 1; i < smooth.size(); ++i) {
    const auto highest = max_cost_along_segment(f.grid, smooth[i - 1], smooth[i]);
    ASSERT_TRUE(highest.has_value());
    EXPECT_LT(*highest, PlanningGrid::kInscribed) << "segment " << i << " crosses inflation";
  }
}

TEST(PathSmoother, ShortcutsRespectTheCostBound) {
  const Fixture f;
  ASSERT_TRUE(f.plan.ok());
  // A shortcut segment (between non-neighbouring plan points) never exceeds the bound; original
  // steps may, where the planner itself had to pass close to a wall (the door).
  PathSmootherOptions options;
  options.waypoint_spacing_m = 0.0;
  options.max_shortcut_cost = 40;
  const std::vector<geometry::Point2D> smooth =
      PathSmoother(options).shortcut(f.grid, f.plan.points_in_map);
  const auto& original = f.plan.points_in_map;
  std::size_t cursor = 0;
  for (std::size_t i = 1; i < smooth.size(); ++i) {
    // Find both ends in the original sequence.
    std::size_t a = cursor;
    while (!(original[a] == smooth[i - 1])) ++a;
    std::size_t b = a + 1;
    while (!(original[b] == smooth[i])) ++b;
    cursor = b;
    if (b == a + 1) continue;
    EXPECT_LE(*max_cost_along_segment(f.grid, smooth[i - 1], smooth[i]), 40);
  }
}

TEST(PathSmoother, DensifiesToTheRequestedSpacing) {
  const std::vector<geometry::Point2D> line{{0.0, 0.0}, {1.0, 0.0}, {1.0, 0.1}};
  const std::vector<geometry::Point2D> dense = PathSmoother::densify(line, 0.3);
  ASSERT_EQ(dense.size(), 6U);  // 4 pieces of 0.25 m, then the short segment untouched
  EXPECT_NEAR(dense[1].x, 0.25, 1e-12);
  EXPECT_EQ(dense[4], (geometry::Point2D{1.0, 0.0}));
  EXPECT_EQ(dense.back(), (geometry::Point2D{1.0, 0.1}));
  for (std::size_t i = 1; i < dense.size(); ++i) {
    EXPECT_LE(std::hypot(dense[i].x - dense[i - 1].x, dense[i].y - dense[i - 1].y), 0.3 + 1e-12);
  }
  EXPECT_EQ(PathSmoother::densify(line, 0.0), line);

  const Fixture f;
  const std::vector<geometry::Point2D> smooth = PathSmoother().smooth(f.grid, f.plan.points_in_map);
  for (std::size_t i = 1; i < smooth.size(); ++i) {
    EXPECT_LE(std::hypot(smooth[i].x - smooth[i - 1].x, smooth[i].y - smooth[i - 1].y), 0.3 + 1e-9);
  }
}

TEST(PathSmoother, LeavesShortPathsAlone) {
  const PlanningGrid grid(10, 10, 0.1, {});
  const PathSmoother smoother;
  EXPECT_TRUE(smoother.smooth(grid, {}).empty());
  const std::vector<geometry::Point2D> two{{0.15, 0.15}, {0.85, 0.85}};
  EXPECT_EQ(smoother.shortcut(grid, two), two);
}

TEST(PathSmoother, RejectsBadSpacing) {
  PathSmootherOptions options;
  options.waypoint_spacing_m = -1.0;
  EXPECT_THROW(PathSmoother{options}, std::invalid_argument);
}

}  // namespace
}  // namespace mobot::planning
