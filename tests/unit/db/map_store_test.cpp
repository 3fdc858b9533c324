#include "db/map_store.h"

#include <gtest/gtest.h>

namespace mobot::db {
namespace {

mapping::OccupancyGrid sample_grid() {
  mapping::OccupancyGrid grid(4, 3, 0.05, {-1.0, 2.0, 0.1}, mapping::OccupancyGrid::kFree);
  grid.set({1, 2}, mapping::OccupancyGrid::kOccupied);
  grid.set({3, 0}, mapping::OccupancyGrid::kUnknown);
  return grid;
}

class MapStoreTest : public ::testing::Test {
 protected:
  Database database_ = Database::open_in_memory();
  MapStore maps_{database_};
};

TEST_F(MapStoreTest, StoresAGridExactly) {
  const auto id = maps_.insert("lab", sample_grid(), 100.0);
  const auto grid = maps_.grid(id);
  ASSERT_TRUE(grid);
  EXPECT_EQ(grid->width(), 4);
  EXPECT_EQ(grid->height(), 3);
  EXPECT_DOUBLE_EQ(grid->resolution_m(), 0.05);
  EXPECT_EQ(grid->origin(), (geometry::Pose2D{-1.0, 2.0, 0.1}));
  EXPECT_EQ(grid->cells(), sample_grid().cells());
  const auto meta = maps_.meta(id);
  ASSERT_TRUE(meta);
  EXPECT_EQ(meta->name, "lab");
  EXPECT_DOUBLE_EQ(meta->created_unix_s, 100.0);
  EXPECT_FALSE(meta->active);
}

TEST_F(MapStoreTest, UnknownIdsAreAbsent) {
  EXPECT_FALSE(maps_.meta(42));
  EXPECT_FALSE(maps_.grid(42));
  EXPECT_FALSE(maps_.activate(42));
  EXPECT_EQ(maps_.remove(42), MapStore::RemoveResult::kNotFound);
}

TEST_F(MapStoreTest, OnlyOneMapIsActive) {
  const auto a = maps_.insert("a", sample_grid(), 1.0);
  const auto b = maps_.insert("b", sample_grid(), 2.0);
  EXPECT_FALSE(maps_.active_id());
  EXPECT_TRUE(maps_.activate(a));
  EXPECT_EQ(maps_.active_id(), a);
  EXPECT_TRUE(maps_.activate(b));
  EXPECT_EQ(maps_.active_id(), b);
  int active = 0;
  for (const auto& meta : maps_.list()) active += meta.active ? 1 : 0;
  EXPECT_EQ(active, 1);
}

TEST_F(MapStoreTest, TheActiveMapCannotBeRemoved) {
  const auto a = maps_.insert("a", sample_grid(), 1.0);
  const auto b = maps_.insert("b", sample_grid(), 2.0);
  maps_.activate(a);
  EXPECT_EQ(maps_.remove(a), MapStore::RemoveResult::kActive);
  EXPECT_TRUE(maps_.meta(a));
  EXPECT_EQ(maps_.remove(b), MapStore::RemoveResult::kRemoved);
  EXPECT_FALSE(maps_.meta(b));
  ASSERT_EQ(maps_.list().size(), 1U);
}

}  // namespace
}  // namespace mobot::db
