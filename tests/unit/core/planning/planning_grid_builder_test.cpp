#include "core/planning/planning_grid_builder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace mobot::planning {
namespace {

using mapping::OccupancyGrid;

constexpr double kRes = 0.05;

OccupancyGrid free_map(int width, int height) {
  return OccupancyGrid(width, height, kRes, {0.0, 0.0, 0.0}, OccupancyGrid::kFree);
}

std::uint8_t expected_band_cost(double distance_m) {
  // costmap_2d: (253 - 1) * exp(-scaling * (d - inscribed)), rounded.
  return static_cast<std::uint8_t>(std::lround(252.0 * std::exp(-10.0 * (distance_m - 0.3))));
}

TEST(PlanningGridBuilder, InflatesASingleObstacleWithCostmapValues) {
  OccupancyGrid map = free_map(41, 41);
  map.set({20, 20}, OccupancyGrid::kOccupied);
  const PlanningGrid grid = PlanningGridBuilder().build(map);
  ASSERT_EQ(grid.width(), 41);
  EXPECT_EQ(grid.cost({20, 20}), PlanningGrid::kLethal);
  // 1..6 cells (0.05..0.30 m) away: inscribed.
  for (int d = 1; d <= 6; ++d) EXPECT_EQ(grid.cost({20 + d, 20}), PlanningGrid::kInscribed) << d;
  EXPECT_EQ(grid.cost({20, 26}), PlanningGrid::kInscribed);
  // 7..11 cells (0.35..0.55 m): the decaying band.
  EXPECT_EQ(grid.cost({27, 20}), expected_band_cost(0.35));
  EXPECT_EQ(grid.cost({27, 20}), 153);
  EXPECT_EQ(grid.cost({20, 9}), expected_band_cost(0.55));
  EXPECT_EQ(grid.cost({20, 9}), 21);
  // Beyond inscribed + 0.25 m: free.
  EXPECT_EQ(grid.cost({32, 20}), PlanningGrid::kFree);
  EXPECT_EQ(grid.cost({0, 0}), PlanningGrid::kFree);
  // Euclidean, not city-block or chessboard: (5, 5) cells is 0.354 m.
  EXPECT_EQ(grid.cost({25, 25}), expected_band_cost(std::hypot(0.25, 0.25)));
  // (4, 4) cells is 0.283 m: inscribed, though 8 steps away in city-block distance.
  EXPECT_EQ(grid.cost({24, 24}), PlanningGrid::kInscribed);
}

TEST(PlanningGridBuilder, CostDecreasesMonotonicallyWithDistance) {
  const PlanningGridBuilder builder;
  std::uint8_t previous = PlanningGrid::kLethal;
  for (double d = 0.0; d < 0.7; d += 0.01) {
    const std::uint8_t cost = builder.cost_at_distance(d);
    EXPECT_LE(cost, previous) << d;
    previous = cost;
  }
  EXPECT_EQ(builder.cost_at_distance(0.0), PlanningGrid::kLethal);
  EXPECT_EQ(builder.cost_at_distance(0.3), PlanningGrid::kInscribed);
  EXPECT_EQ(builder.cost_at_distance(0.3001), 252);
  EXPECT_EQ(builder.cost_at_distance(0.56), PlanningGrid::kFree);
}

TEST(PlanningGridBuilder, OccupancyThresholdDecidesWhatIsAnObstacle) {
  OccupancyGrid map = free_map(30, 30);
  map.set({5, 5}, 64);
  map.set({20, 20}, 65);
  const PlanningGrid grid = PlanningGridBuilder().build(map);
  EXPECT_EQ(grid.cost({5, 5}), PlanningGrid::kFree);
  EXPECT_EQ(grid.cost({20, 20}), PlanningGrid::kLethal);
}

TEST(PlanningGridBuilder, UnknownBlocksAndInflatesByDefault) {
  OccupancyGrid map = free_map(40, 10);
  for (int y = 0; y < 10; ++y) map.set({0, y}, OccupancyGrid::kUnknown);
  const PlanningGrid grid = PlanningGridBuilder().build(map);
  EXPECT_EQ(grid.cost({0, 5}), PlanningGrid::kUnknown);
  EXPECT_FALSE(grid.is_traversable({0, 5}));
  EXPECT_EQ(grid.cost({3, 5}), PlanningGrid::kInscribed);
  EXPECT_EQ(grid.cost({30, 5}), PlanningGrid::kFree);
}

TEST(PlanningGridBuilder, UnknownCanPlanAsFree) {
  OccupancyGrid map = free_map(40, 10);
  for (int y = 0; y < 10; ++y) map.set({0, y}, OccupancyGrid::kUnknown);
  PlanningGridOptions options;
  options.unknown_is_obstacle = false;
  const PlanningGrid grid = PlanningGridBuilder(options).build(map);
  EXPECT_EQ(grid.cost({0, 5}), PlanningGrid::kFree);
  EXPECT_EQ(grid.cost({3, 5}), PlanningGrid::kFree);
}

TEST(PlanningGridBuilder, MergesACoarserRotatedExtraGridAndPoints) {
  OccupancyGrid map = free_map(100, 100);  // 5 x 5 m
  // A 0.2 m grid (like IPaBD's) whose cell (1, 1) covers [2.2, 2.4) x [2.2, 2.4) in the map.
  OccupancyGrid extra(5, 5, 0.2, {2.0, 2.0, 0.0}, OccupancyGrid::kFree);
  extra.set({1, 1}, OccupancyGrid::kOccupied);
  const std::vector<OccupancyGrid> grids{extra};
  const std::vector<geometry::Point2D> points{{0.52, 4.03}, {99.0, 99.0}};  // second is off-map
  PlanningGridOptions options;
  options.inscribed_radius_m = 0.0;
  options.inflation_margin_m = 0.0;
  ExtraObstacles obstacles;
  obstacles.grids = grids;
  obstacles.points_in_map = points;
  const PlanningGrid grid = PlanningGridBuilder(options).build(map, obstacles);
  int lethal = 0;
  for (int y = 0; y < 100; ++y) {
    for (int x = 0; x < 100; ++x) lethal += grid.cost({x, y}) == PlanningGrid::kLethal ? 1 : 0;
  }
  EXPECT_EQ(lethal, 16 + 1);  // 4 x 4 cells of 0.05 m under the 0.2 m cell, plus the point
  EXPECT_EQ(grid.cost({44, 44}), PlanningGrid::kLethal);
  EXPECT_EQ(grid.cost({47, 47}), PlanningGrid::kLethal);
  EXPECT_EQ(grid.cost({48, 47}), PlanningGrid::kFree);
  EXPECT_EQ(grid.cost({43, 44}), PlanningGrid::kFree);
  EXPECT_EQ(grid.cost({10, 80}), PlanningGrid::kLethal);

  // Rotated by 45 degrees about its origin, the same cell covers a diamond.
  OccupancyGrid rotated(5, 5, 0.2, {2.5, 2.5, std::numbers::pi / 4.0}, OccupancyGrid::kFree);
  rotated.set({0, 0}, OccupancyGrid::kOccupied);
  const std::vector<OccupancyGrid> rotated_grids{rotated};
  ExtraObstacles rotated_extra;
  rotated_extra.grids = rotated_grids;
  const PlanningGrid diamond = PlanningGridBuilder(options).build(map, rotated_extra);
  const auto centre = diamond.cell_at({2.5, 2.5 + 0.1414});  // the diamond's centre
  ASSERT_TRUE(centre.has_value());
  EXPECT_EQ(diamond.cost(*centre), PlanningGrid::kLethal);
  EXPECT_EQ(diamond.cost(*diamond.cell_at({2.5 + 0.13, 2.5 + 0.01})), PlanningGrid::kFree);
}

TEST(PlanningGridBuilder, AnExtraObstacleInUnknownSpaceIsLethal) {
  OccupancyGrid map(10, 10, kRes, {}, OccupancyGrid::kUnknown);
  const std::vector<geometry::Point2D> points{{0.26, 0.26}};
  ExtraObstacles extra;
  extra.points_in_map = points;
  const PlanningGrid grid = PlanningGridBuilder().build(map, extra);
  EXPECT_EQ(grid.cost({5, 5}), PlanningGrid::kLethal);
  EXPECT_EQ(grid.cost({4, 5}), PlanningGrid::kUnknown);
}

TEST(PlanningGridBuilder, KeepsTheMapGeometry) {
  const OccupancyGrid map(20, 10, 0.1, {-1.0, 2.0, 0.3}, OccupancyGrid::kFree);
  const PlanningGrid grid = PlanningGridBuilder().build(map);
  EXPECT_EQ(grid.width(), 20);
  EXPECT_EQ(grid.height(), 10);
  EXPECT_DOUBLE_EQ(grid.resolution_m(), 0.1);
  EXPECT_EQ(grid.origin(), map.origin());
  const auto cell = grid.cell_at(map.cell_center({7, 3}));
  ASSERT_TRUE(cell.has_value());
  EXPECT_EQ(*cell, (mapping::CellIndex{7, 3}));
}

TEST(PlanningGridBuilder, EmptyMapGivesEmptyGrid) {
  EXPECT_TRUE(PlanningGridBuilder().build(OccupancyGrid()).empty());
  EXPECT_FALSE(PlanningGrid().cell_at({0.0, 0.0}).has_value());
}

TEST(PlanningGridBuilder, RejectsBadOptions) {
  PlanningGridOptions options;
  options.inscribed_radius_m = std::nan("");
  EXPECT_THROW(PlanningGridBuilder{options}, std::invalid_argument);
  options.inscribed_radius_m = -0.1;
  EXPECT_THROW(PlanningGridBuilder{options}, std::invalid_argument);
}

TEST(PlanningGrid, RejectsNonFiniteAndFarPoints) {
  const PlanningGrid grid(10, 10, 0.1, {});
  EXPECT_FALSE(grid.cell_at({std::nan(""), 0.0}).has_value());
  EXPECT_FALSE(grid.cell_at({1e300, 0.0}).has_value());
  EXPECT_FALSE(grid.cell_at({-1e-9, 0.5}).has_value());
  EXPECT_TRUE(grid.cell_at({0.999, 0.999}).has_value());
  EXPECT_THROW(PlanningGrid(0, 3, 0.1, {}), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::planning
