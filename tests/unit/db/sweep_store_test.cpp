#include "db/sweep_store.h"

#include <gtest/gtest.h>

namespace mobot::db {
namespace {

class SweepStoreTest : public ::testing::Test {
 protected:
  Database database_ = Database::open_in_memory();
  SweepStore sweeps_{database_};
};

TEST_F(SweepStoreTest, ARunningSweepIsStoredAtOnceAndFinishesWithItsCloudAndMap) {
  const auto id = sweeps_.insert_running(10.0, 1.0, 81, 12.5, 1000.0, std::nullopt);
  auto record = sweeps_.get(id);
  ASSERT_TRUE(record);
  EXPECT_EQ(record->status, "running");
  EXPECT_EQ(record->scans, 81);
  EXPECT_DOUBLE_EQ(record->started_t, 12.5);
  EXPECT_FALSE(record->ended_t);
  EXPECT_FALSE(sweeps_.cloud(id)) << "no cloud before it is done";
  EXPECT_FALSE(sweeps_.obstacle_map(id));

  const perception::PointCloud cloud{{1.0F, 2.0F, 0.5F, 0.25F}, {-3.5F, 0.125F, 1.75F, 1.0F}};
  mapping::OccupancyGrid map(3, 2, 0.2, {-6.0, -2.0, 0.0}, mapping::OccupancyGrid::kUnknown);
  map.set({1, 1}, mapping::OccupancyGrid::kOccupied);
  map.set({0, 0}, mapping::OccupancyGrid::kFree);
  ASSERT_TRUE(sweeps_.finish(id, 22.5, cloud, map));
  EXPECT_FALSE(sweeps_.finish(id, 23.0, cloud, map)) << "only a running sweep finishes";

  record = sweeps_.get(id);
  EXPECT_EQ(record->status, "done");
  EXPECT_EQ(record->points, 2);
  EXPECT_DOUBLE_EQ(*record->ended_t, 22.5);
  const auto stored = sweeps_.cloud(id);
  ASSERT_TRUE(stored);
  ASSERT_EQ(stored->size(), 2U);
  EXPECT_FLOAT_EQ((*stored)[1].x_m, -3.5F);
  EXPECT_FLOAT_EQ((*stored)[1].intensity, 1.0F);
  const auto stored_map = sweeps_.obstacle_map(id);
  ASSERT_TRUE(stored_map);
  EXPECT_EQ(stored_map->cells(), map.cells());
  EXPECT_DOUBLE_EQ(stored_map->origin().x, -6.0);
  EXPECT_DOUBLE_EQ(stored_map->resolution_m(), 0.2);
}

TEST_F(SweepStoreTest, OnlyAFinishedSweepCanBeRemoved) {
  const auto running = sweeps_.insert_running(10.0, 1.0, 81, 1.0, 1000.0, std::nullopt);
  const auto done = sweeps_.insert_running(10.0, 1.0, 81, 2.0, 1001.0, std::nullopt);
  ASSERT_TRUE(sweeps_.finish(done, 12.0, {{1.0F, 2.0F, 0.5F, 0.25F}},
                             mapping::OccupancyGrid(2, 2, 0.2, {}, mapping::OccupancyGrid::kFree)));
  EXPECT_EQ(sweeps_.remove(running), SweepStore::RemoveResult::kRunning);
  EXPECT_EQ(sweeps_.remove(done), SweepStore::RemoveResult::kRemoved);
  EXPECT_EQ(sweeps_.remove(done), SweepStore::RemoveResult::kNotFound);
  EXPECT_FALSE(sweeps_.get(done));
  EXPECT_FALSE(sweeps_.cloud(done));
  ASSERT_EQ(sweeps_.list().size(), 1U);
  EXPECT_EQ(sweeps_.list()[0].id, running);
}

TEST_F(SweepStoreTest, FailedAndInterruptedSweepsKeepTheirReason) {
  const auto a = sweeps_.insert_running(42.0, 0.25, 100, 1.0, 1000.0, std::nullopt);
  const auto b = sweeps_.insert_running(10.0, 0.5, 40, 2.0, 1001.0, std::nullopt);
  ASSERT_TRUE(sweeps_.fail(a, 3.0, "estop"));
  EXPECT_FALSE(sweeps_.fail(a, 4.0, "again"));
  EXPECT_EQ(sweeps_.fail_interrupted("server stopped"), 1);
  const auto all = sweeps_.list();
  ASSERT_EQ(all.size(), 2U);
  EXPECT_EQ(all[0].status, "failed");
  EXPECT_EQ(all[0].reason, "estop");
  EXPECT_EQ(all[1].id, b);
  EXPECT_EQ(all[1].status, "failed");
  EXPECT_EQ(all[1].reason, "server stopped");
  EXPECT_FALSE(sweeps_.get(999));
  EXPECT_FALSE(sweeps_.cloud(a));
}

}  // namespace
}  // namespace mobot::db
