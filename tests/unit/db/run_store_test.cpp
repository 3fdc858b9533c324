#include "db/run_store.h"

#include <gtest/gtest.h>

namespace mobot::db {
namespace {

class RunStoreTest : public ::testing::Test {
 protected:
  Database database_ = Database::open_in_memory();
  RunStore runs_{database_};
};

TEST_F(RunStoreTest, AppendsTrajectoryAndEventsInOrder) {
  const auto id = runs_.start_run("first", 1000.0);
  runs_.append(id, {{0.0, 1, 2, 3}, {0.1, 1.1, 2, 3}}, {{0.05, "estop", R"({"engaged":true})"}},
               0.1);
  // After a simulator reset the robot clock restarts: order is by recording, not by t.
  runs_.append(id, {{0.0, 5, 5, 0}}, {}, 0.2);
  const auto trajectory = runs_.trajectory(id);
  ASSERT_EQ(trajectory.size(), 3U);
  EXPECT_DOUBLE_EQ(trajectory[1].x, 1.1);
  EXPECT_DOUBLE_EQ(trajectory[2].x, 5.0);
  const auto events = runs_.events(id);
  ASSERT_EQ(events.size(), 1U);
  EXPECT_EQ(events[0].kind, "estop");
  EXPECT_EQ(events[0].detail_json, R"({"engaged":true})");
  const auto run = runs_.get(id);
  ASSERT_TRUE(run);
  EXPECT_DOUBLE_EQ(run->distance_m, 0.2);
  EXPECT_FALSE(run->ended_unix_s);
}

TEST_F(RunStoreTest, CountsGoalOutcomesFromEvents) {
  const auto id = runs_.start_run("goals", 1.0);
  runs_.append(id, {},
               {{1, "goal", R"({"id":1,"status":"active"})"},
                {2, "goal", R"({"id":1,"status":"succeeded"})"},
                {3, "goal", R"({"id":2,"status":"canceled","reason":"preempted"})"},
                {4, "goal", R"({"id":3,"status":"failed"})"},
                {5, "goal", R"({"id":4,"status":"succeeded"})"}},
               0);
  const auto run = runs_.get(id);
  ASSERT_TRUE(run);
  EXPECT_EQ(run->goals.succeeded, 2);
  EXPECT_EQ(run->goals.failed, 1);
  EXPECT_EQ(run->goals.canceled, 1);
}

TEST_F(RunStoreTest, EndingARunRecordsItsEnd) {
  const auto id = runs_.start_run("r", 10.0);
  runs_.end_run(id, 20.0, 3.5);
  const auto run = runs_.get(id);
  ASSERT_TRUE(run && run->ended_unix_s);
  EXPECT_DOUBLE_EQ(*run->ended_unix_s, 20.0);
  EXPECT_DOUBLE_EQ(run->distance_m, 3.5);
}

TEST_F(RunStoreTest, ABatchForAnUnknownRunIsRejectedWhole) {
  EXPECT_THROW(runs_.append(77, {{0, 0, 0, 0}}, {{0, "x", "{}"}}, 0), DbError);
  EXPECT_TRUE(runs_.trajectory(77).empty());
  EXPECT_TRUE(runs_.events(77).empty());
  EXPECT_THROW(runs_.end_run(77, 1, 0), DbError);
}

TEST_F(RunStoreTest, DanglingRunsAreClosedAtTheirLastSample) {
  const auto killed = runs_.start_run("killed", 100.0);
  runs_.append(killed, {{2.0, 0, 0, 0}, {7.0, 0, 0, 0}}, {}, 0);
  const auto closed = runs_.start_run("closed", 50.0);
  runs_.end_run(closed, 60.0, 0);
  EXPECT_EQ(runs_.close_dangling_runs(1000.0), 1);
  EXPECT_DOUBLE_EQ(*runs_.get(killed)->ended_unix_s, 105.0);
  EXPECT_DOUBLE_EQ(*runs_.get(closed)->ended_unix_s, 60.0);
  EXPECT_EQ(runs_.close_dangling_runs(1000.0), 0);
}

TEST_F(RunStoreTest, ListsRunsOldestFirst) {
  runs_.start_run("a", 1);
  runs_.start_run("b", 2);
  const auto runs = runs_.list();
  ASSERT_EQ(runs.size(), 2U);
  EXPECT_EQ(runs[0].name, "a");
  EXPECT_EQ(runs[1].name, "b");
  EXPECT_FALSE(runs_.get(999));
}

}  // namespace
}  // namespace mobot::db
