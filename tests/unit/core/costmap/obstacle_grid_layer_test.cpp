#include "core/costmap/obstacle_grid_layer.h"

#include <gtest/gtest.h>

#include <numbers>

#include "core/costmap/grid_shift.h"

namespace mobot::costmap {
namespace {

using mapping::OccupancyGrid;
using planning::PlanningGrid;

int count_lethal(const PlanningGrid& grid) {
  int n = 0;
  for (const auto cost : grid.costs()) n += cost == PlanningGrid::kLethal;
  return n;
}

TEST(ObstacleGridLayer, ACoarseCellMarksEveryMasterCellItCovers) {
  // A 0.2 m grid (IPaBD's) whose cell (1, 1) covers [2.2, 2.4) x [2.2, 2.4).
  OccupancyGrid coarse(5, 5, 0.2, {2.0, 2.0, 0.0}, OccupancyGrid::kFree);
  coarse.set({1, 1}, OccupancyGrid::kOccupied);
  coarse.set({3, 3}, OccupancyGrid::kUnknown);
  PlanningGrid master(100, 100, 0.05, {});
  ObstacleGridLayer::rasterise(coarse, 65, master, CellBounds::of_size(100, 100));
  EXPECT_EQ(count_lethal(master), 16);
  EXPECT_EQ(master.cost({44, 44}), PlanningGrid::kLethal);
  EXPECT_EQ(master.cost({47, 47}), PlanningGrid::kLethal);
  EXPECT_EQ(master.cost({48, 47}), PlanningGrid::kFree);
  // Only within the bounds.
  PlanningGrid part(100, 100, 0.05, {});
  ObstacleGridLayer::rasterise(coarse, 65, part, CellBounds{46, 0, 99, 99});
  EXPECT_EQ(count_lethal(part), 8);
}

TEST(ObstacleGridLayer, AFineCellMarksTheMasterCellUnderItsCentre) {
  // 0.01 m cells: one of them covers no master cell centre.
  OccupancyGrid fine(50, 50, 0.01, {0.0, 0.0, 0.0}, OccupancyGrid::kFree);
  fine.set({1, 1}, OccupancyGrid::kOccupied);
  PlanningGrid master(20, 20, 0.05, {});
  ObstacleGridLayer::rasterise(fine, 65, master, CellBounds::of_size(20, 20));
  EXPECT_EQ(count_lethal(master), 1);
  EXPECT_EQ(master.cost({0, 0}), PlanningGrid::kLethal);
}

TEST(ObstacleGridLayer, ARotatedGridMarksADiamond) {
  OccupancyGrid rotated(5, 5, 0.2, {2.5, 2.5, std::numbers::pi / 4.0}, OccupancyGrid::kFree);
  rotated.set({0, 0}, OccupancyGrid::kOccupied);
  PlanningGrid master(100, 100, 0.05, {});
  ObstacleGridLayer::rasterise(rotated, 65, master, CellBounds::of_size(100, 100));
  EXPECT_EQ(master.cost(*master.cell_at({2.5, 2.5 + 0.1414})), PlanningGrid::kLethal);
  EXPECT_EQ(master.cost(*master.cell_at({2.5 + 0.13, 2.5 + 0.01})), PlanningGrid::kFree);
}

TEST(ObstacleGridLayer, AsALayerMarksOnlyWhenTheGridsChangeAndFollowsAWindow) {
  OccupancyGrid obstacles(40, 40, 0.1, {}, OccupancyGrid::kFree);
  obstacles.set({20, 20}, OccupancyGrid::kOccupied);
  ObstacleGridLayer layer;
  layer.set_grid(obstacles);
  PlanningGrid master(20, 20, 0.05, {1.5, 1.5, 0.0});
  CellBounds bounds;
  layer.update_bounds(master, bounds);
  EXPECT_EQ(bounds, CellBounds::of_size(20, 20));
  layer.update(master, bounds);
  EXPECT_EQ(count_lethal(master), 4);  // [2.0, 2.1)^2
  EXPECT_EQ(master.cost({10, 10}), PlanningGrid::kLethal);
  CellBounds again;
  layer.update_bounds(master, again);
  EXPECT_TRUE(again.empty());

  // The window moves 12 cells right: the obstacle leaves it, then another one enters.
  obstacles.set({25, 20}, OccupancyGrid::kOccupied);
  layer.set_grid(obstacles);
  layer.update_bounds(master, again);
  shift_grid(master, 12, 0, PlanningGrid::kFree);
  layer.shift(master, 12, 0);
  PlanningGrid shifted = master;
  std::fill(shifted.mutable_costs().begin(), shifted.mutable_costs().end(), PlanningGrid::kFree);
  layer.update(shifted, CellBounds::of_size(20, 20));
  PlanningGrid fresh(20, 20, 0.05, master.origin());
  ObstacleGridLayer::rasterise(obstacles, 65, fresh, CellBounds::of_size(20, 20));
  EXPECT_EQ(shifted.costs(), fresh.costs());
  EXPECT_EQ(count_lethal(fresh), 4);  // [2.5, 2.6) x [2.0, 2.1)
}

TEST(ObstacleGridLayer, UnknownAndFreeCellsAddNothing) {
  OccupancyGrid grid(4, 4, 0.05, {}, OccupancyGrid::kUnknown);
  grid.set({1, 1}, 64);
  PlanningGrid master(4, 4, 0.05, {});
  ObstacleGridLayer::rasterise(grid, 65, master, CellBounds::of_size(4, 4));
  EXPECT_EQ(count_lethal(master), 0);
  ObstacleGridLayer::rasterise(OccupancyGrid(), 65, master, CellBounds::of_size(4, 4));
  EXPECT_EQ(count_lethal(master), 0);
}

}  // namespace
}  // namespace mobot::costmap
