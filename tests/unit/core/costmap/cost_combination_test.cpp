#include "core/costmap/cost_combination.h"

#include <gtest/gtest.h>

namespace mobot::costmap {
namespace {

using planning::PlanningGrid;

TEST(CostCombination, MaxSkipsUnknownLayerCellsAndTakesOverUnknownMasterCells) {
  std::uint8_t master = 100;
  combine_max(PlanningGrid::kUnknown, master);
  EXPECT_EQ(master, 100);
  combine_max(50, master);
  EXPECT_EQ(master, 100);
  combine_max(PlanningGrid::kLethal, master);
  EXPECT_EQ(master, PlanningGrid::kLethal);
  master = PlanningGrid::kUnknown;
  combine_max(PlanningGrid::kFree, master);
  EXPECT_EQ(master, PlanningGrid::kFree);
}

TEST(CostCombination, WritesOnlyInsideTheBounds) {
  PlanningGrid layer(4, 4, 0.1, {}, PlanningGrid::kLethal);
  layer.set_cost({1, 1}, PlanningGrid::kUnknown);
  PlanningGrid max_master(4, 4, 0.1, {}, 10);
  write_max(layer, max_master, {1, 1, 2, 2});
  EXPECT_EQ(max_master.cost({0, 0}), 10);
  EXPECT_EQ(max_master.cost({1, 1}), 10);
  EXPECT_EQ(max_master.cost({2, 2}), PlanningGrid::kLethal);
  PlanningGrid overwritten(4, 4, 0.1, {}, 10);
  write_overwrite(layer, overwritten, {1, 1, 5, 5});  // clipped to the grid
  EXPECT_EQ(overwritten.cost({0, 3}), 10);
  EXPECT_EQ(overwritten.cost({1, 1}), PlanningGrid::kUnknown);
  EXPECT_EQ(overwritten.cost({3, 3}), PlanningGrid::kLethal);
}

}  // namespace
}  // namespace mobot::costmap
