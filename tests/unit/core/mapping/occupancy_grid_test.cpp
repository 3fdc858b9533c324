#include "core/mapping/occupancy_grid.h"

#include <gtest/gtest.h>

namespace mobot::mapping {
namespace {

TEST(OccupancyGrid, MapsPointsToCellsAndBack) {
  const OccupancyGrid grid(10, 5, 0.5, {-1.0, -2.0, 0.0}, OccupancyGrid::kFree);
  const auto cell = grid.cell_at({0.2, 0.1});
  ASSERT_TRUE(cell.has_value());
  EXPECT_EQ(*cell, (CellIndex{2, 4}));
  const auto center = grid.cell_center(*cell);
  EXPECT_DOUBLE_EQ(center.x, 0.25);
  EXPECT_DOUBLE_EQ(center.y, 0.25);
  EXPECT_FALSE(grid.cell_at({-1.01, 0.0}).has_value());
  EXPECT_FALSE(grid.cell_at({4.0, 0.0}).has_value());
}

TEST(OccupancyGrid, UnknownIsNotOccupied) {
  OccupancyGrid grid(2, 2, 1.0, {}, OccupancyGrid::kUnknown);
  EXPECT_FALSE(grid.is_occupied({0, 0}));
  grid.set({1, 1}, 70);
  EXPECT_TRUE(grid.is_occupied({1, 1}));
  grid.set({1, 0}, 40);
  EXPECT_FALSE(grid.is_occupied({1, 0}));
}

TEST(OccupancyGrid, RejectsBadDimensions) {
  EXPECT_THROW(OccupancyGrid(0, 1, 1.0, {}), std::invalid_argument);
  EXPECT_THROW(OccupancyGrid(1, 1, 0.0, {}), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::mapping
