#include "drivers/sim/world_slice.h"

#include <gtest/gtest.h>

#include "tests/unit/drivers/sim/sim_test_support.h"

namespace mobot::sim {
namespace {

using mapping::OccupancyGrid;

int occupied_cells(const OccupancyGrid& grid) {
  int count = 0;
  for (const auto cell : grid.cells()) count += (cell != OccupancyGrid::kUnknown && cell >= 65);
  return count;
}

TEST(WorldSlice, DrawsOnlyBoxesThatReachTheHeight) {
  World world = testing::empty_world(20, 20, 0.1);
  world.floor.set({0, 0}, OccupancyGrid::kOccupied);
  world.boxes.push_back({0.5, 0.5, 1.0, 0.8, 0.0, 0.9, "cabinet"});  // 5 x 3 cells
  world.boxes.push_back({1.0, 1.0, 1.2, 1.2, 0.8, 1.0, "beam"});     // 2 x 2 cells
  const OccupancyGrid laser_plane = slice_at_height(world, 0.4);
  EXPECT_EQ(occupied_cells(laser_plane), 1 + 15);
  EXPECT_TRUE(laser_plane.is_occupied({5, 5}));
  EXPECT_TRUE(laser_plane.is_occupied({9, 7}));
  EXPECT_FALSE(laser_plane.is_occupied({10, 7}));  // the box only touches this cell
  EXPECT_FALSE(laser_plane.is_occupied({9, 8}));
  EXPECT_EQ(occupied_cells(slice_at_height(world, 0.85)), 1 + 15 + 4);
  EXPECT_EQ(occupied_cells(slice_at_height(world, 0.95)), 1 + 4);
  EXPECT_EQ(occupied_cells(world.floor), 1);  // the floor plan itself is untouched
}

TEST(WorldSlice, RasterizesPartialCellsAndClipsToTheGrid) {
  OccupancyGrid grid(10, 10, 1.0, {}, OccupancyGrid::kFree);
  rasterize_box({-5.0, 8.5, 0.2, 20.0, 0.0, 1.0, "edge"}, grid);
  EXPECT_EQ(occupied_cells(grid), 2);  // cells (0, 8) and (0, 9)
  EXPECT_TRUE(grid.is_occupied({0, 8}));
  EXPECT_TRUE(grid.is_occupied({0, 9}));
}

}  // namespace
}  // namespace mobot::sim
