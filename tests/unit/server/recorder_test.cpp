#include "server/recorder.h"

#include <gtest/gtest.h>

namespace mobot::server {
namespace {

class RecorderTest : public ::testing::Test {
 protected:
  db::Database database_ = db::Database::open_in_memory();
  db::RunStore runs_{database_};
  std::int64_t run_id_ = runs_.start_run("test", 1000.0);
};

TEST_F(RecorderTest, FlushPutsEverythingRecordedOnDisk) {
  Recorder recorder(runs_, run_id_, 5000);  // a long period: only flush() writes
  recorder.record_pose(0.0, 1, 2, 3);
  recorder.record_pose(0.05, 1.1, 2, 3);
  recorder.record_event(0.02, "estop", R"({"engaged":true})");
  recorder.set_distance(0.1);
  recorder.flush();
  EXPECT_EQ(runs_.trajectory(run_id_).size(), 2U);
  ASSERT_EQ(runs_.events(run_id_).size(), 1U);
  EXPECT_EQ(runs_.events(run_id_)[0].kind, "estop");
  EXPECT_DOUBLE_EQ(runs_.get(run_id_)->distance_m, 0.1);
}

TEST_F(RecorderTest, WritesPeriodicallyWithoutFlush) {
  Recorder recorder(runs_, run_id_, 10);
  recorder.record_pose(0.0, 1, 2, 3);
  for (int i = 0; i < 500 && runs_.trajectory(run_id_).empty(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(runs_.trajectory(run_id_).size(), 1U);
}

TEST_F(RecorderTest, StopWritesTheRestAndClosesTheRun) {
  Recorder recorder(runs_, run_id_, 5000);
  recorder.record_pose(0.0, 1, 2, 3);
  recorder.set_distance(4.5);
  recorder.stop(2000.0);
  EXPECT_EQ(runs_.trajectory(run_id_).size(), 1U);
  const auto run = runs_.get(run_id_);
  ASSERT_TRUE(run && run->ended_unix_s);
  EXPECT_DOUBLE_EQ(*run->ended_unix_s, 2000.0);
  EXPECT_DOUBLE_EQ(run->distance_m, 4.5);
  recorder.flush();  // after stop: returns at once instead of waiting forever
}

TEST(RecorderFailure, AFailedBatchIsKeptAndCounted) {
  db::Database database = db::Database::open_in_memory();
  db::RunStore runs(database);
  // The run does not exist: every batch fails, and nothing recorded is thrown away.
  Recorder recorder(runs, 999, 5000);
  recorder.record_event(0.0, "fault", "{}");
  recorder.flush();
  recorder.flush();
  EXPECT_NE(recorder.metrics_text().find("mobot_recorder_write_failures_total 2"),
            std::string::npos);
  EXPECT_TRUE(runs.events(999).empty());
}

}  // namespace
}  // namespace mobot::server
