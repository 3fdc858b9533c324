#include "core/mapping/map_tiles.h"

#include <gtest/gtest.h>

namespace mobot::mapping {
namespace {

OccupancyGrid grid_at(double origin_x, double origin_y, int width, int height) {
  return OccupancyGrid(width, height, 0.05, {origin_x, origin_y, 0.0});
}

TEST(MapTiler, SendsOnlyKnownTilesThenOnlyChangedOnes) {
  MapTiler tiler(4);
  OccupancyGrid grid = grid_at(-0.2, 0.0, 8, 4);  // two tiles: (-1, 0) and (0, 0)
  grid.set({5, 1}, OccupancyGrid::kOccupied);
  auto update = tiler.changed_tiles(grid);
  ASSERT_EQ(update.tiles.size(), 1U) << "an all-unknown tile is not sent";
  EXPECT_EQ(update.tiles[0].x, 0);
  EXPECT_EQ(update.tiles[0].y, 0);
  EXPECT_EQ(update.tiles[0].cells[1 * 4 + 1], OccupancyGrid::kOccupied);
  EXPECT_TRUE(tiler.changed_tiles(grid).tiles.empty()) << "nothing changed";
  grid.set({0, 0}, OccupancyGrid::kFree);
  update = tiler.changed_tiles(grid);
  ASSERT_EQ(update.tiles.size(), 1U);
  EXPECT_EQ(update.tiles[0].x, -1);
}

TEST(MapTiler, AGrownMapKeepsItsTilesPlaces) {
  MapTiler tiler(4);
  OccupancyGrid small = grid_at(0.0, 0.0, 4, 4);
  small.set({1, 1}, OccupancyGrid::kOccupied);
  ASSERT_EQ(tiler.changed_tiles(small).tiles.size(), 1U);
  // The same content, now inside a larger map that starts a tile further left and down.
  OccupancyGrid grown = grid_at(-0.2, -0.2, 12, 8);
  grown.set({5, 5}, OccupancyGrid::kOccupied);
  EXPECT_TRUE(tiler.changed_tiles(grown).tiles.empty());
  grown.set({10, 1}, OccupancyGrid::kFree);
  const auto update = tiler.changed_tiles(grown);
  ASSERT_EQ(update.tiles.size(), 1U);
  EXPECT_EQ(update.tiles[0].x, 1);
  EXPECT_EQ(update.tiles[0].y, -1);
  // Cells beyond the grid's edge inside a partial tile are unknown.
  OccupancyGrid partial = grid_at(0.0, 0.0, 3, 3);
  MapTiler other(4);
  partial.set({2, 2}, OccupancyGrid::kFree);
  const auto cut = other.changed_tiles(partial);
  ASSERT_EQ(cut.tiles.size(), 1U);
  EXPECT_EQ(cut.tiles[0].cells[3 * 4 + 3], OccupancyGrid::kUnknown);
}

TEST(MapTiler, RefusesAMapOffTheLatticeOrWithAnotherResolution) {
  MapTiler tiler(4);
  EXPECT_THROW(tiler.changed_tiles(grid_at(0.01, 0.0, 4, 4)), std::invalid_argument);
  EXPECT_THROW(tiler.changed_tiles(OccupancyGrid(4, 4, 0.05, {0, 0, 0.3})), std::invalid_argument);
  OccupancyGrid grid = grid_at(0.0, 0.0, 4, 4);
  grid.set({0, 0}, OccupancyGrid::kFree);
  tiler.changed_tiles(grid);
  EXPECT_THROW(tiler.changed_tiles(OccupancyGrid(4, 4, 0.1, {})), std::invalid_argument);
  EXPECT_THROW(MapTiler(0), std::invalid_argument);
  EXPECT_TRUE(tiler.changed_tiles(OccupancyGrid()).tiles.empty());
}

}  // namespace
}  // namespace mobot::mapping
