#include "drivers/modbus/modbus_poll_schedule.h"

#include <gtest/gtest.h>

#include <map>
#include <stdexcept>
#include <vector>

namespace mobot::drivers::modbus {
namespace {

struct Read {
  int node = 0;
  double at_s = 0.0;
};

// Runs the schedule from 0 to `duration_s`: every read succeeds and keeps the bus for its
// transaction time (or no time at all), as a master following the schedule would.
std::vector<Read> simulate(ModbusPollSchedule& schedule, double duration_s, bool reads_take_time) {
  std::vector<Read> reads;
  double now_s = 0.0;
  while (now_s < duration_s) {
    const std::optional<PollTarget> target = schedule.next(now_s);
    if (!target) {
      now_s = schedule.next_due_s();
      continue;
    }
    reads.push_back({target->node, now_s});
    if (reads_take_time) now_s += schedule.transaction_s(target->kind);
    schedule.record_success(target->node, now_s);
  }
  return reads;
}

std::map<int, int> count_by_node(const std::vector<Read>& reads) {
  std::map<int, int> counts;
  for (const Read& read : reads) ++counts[read.node];
  return counts;
}

TEST(ModbusPollSchedule, EachNodeIsReadAtItsRate) {
  ModbusPollSchedule schedule{PollScheduleOptions{}};
  EXPECT_DOUBLE_EQ(schedule.rate_scale(), 1.0);
  for (const bool reads_take_time : {false, true}) {
    ModbusPollSchedule fresh{PollScheduleOptions{}};
    const std::map<int, int> counts = count_by_node(simulate(fresh, 10.0, reads_take_time));
    EXPECT_NEAR(counts.at(1), 100, 1);  // compass, 10 Hz
    for (int sonar = 2; sonar <= 9; ++sonar) EXPECT_NEAR(counts.at(sonar), 100, 1);
    EXPECT_NEAR(counts.at(10), 200, 1);  // limit switch, 20 Hz
  }
}

TEST(ModbusPollSchedule, SonarsTakeTurnsSpreadEvenlyOverTheirPeriod) {
  ModbusPollSchedule schedule{PollScheduleOptions{}};
  std::vector<Read> sonar_reads;
  for (const Read& read : simulate(schedule, 2.0, true)) {
    if (read.node >= 2 && read.node <= 9) sonar_reads.push_back(read);
  }
  ASSERT_GT(sonar_reads.size(), 100u);
  for (std::size_t i = 1; i < sonar_reads.size(); ++i) {
    EXPECT_EQ(sonar_reads[i].node, 2 + (sonar_reads[i - 1].node - 2 + 1) % 8);
    // One every 12.5 ms, give or take the reads of the other nodes that fell in between.
    EXPECT_NEAR(sonar_reads[i].at_s - sonar_reads[i - 1].at_s, 0.0125, 0.004);
  }
}

TEST(ModbusPollSchedule, OneRoundOfTheTenNodesAt115200Baud) {
  ModbusPollSchedule schedule{PollScheduleOptions{}};
  // Nine register reads of 8 + 7 bytes and one bit read of 8 + 6, 10 bits a byte, and the
  // 2 ms turnaround of each.
  const double expected_s = (9 * 15 + 14) * 10.0 / 115200.0 + 10 * 0.002;
  EXPECT_NEAR(schedule.round_s(), expected_s, 1e-12);
  EXPECT_NEAR(schedule.round_s(), 0.0329, 0.0001);
  // 110 reads a second of about 3.3 ms each.
  EXPECT_NEAR(schedule.requested_load(), 0.362, 0.001);
}

TEST(ModbusPollSchedule, AnOverbookedBusScalesEveryRateAlike) {
  PollScheduleOptions options;
  options.baud = 9600;  // 15.6 ms for a register read
  options.turnaround_s = 0.004;
  ModbusPollSchedule schedule(options);
  ASSERT_LT(schedule.rate_scale(), 1.0);
  EXPECT_NEAR(schedule.requested_load() * schedule.rate_scale(), 0.8, 1e-12);
  const std::vector<Read> reads = simulate(schedule, 20.0, true);
  const std::map<int, int> counts = count_by_node(reads);
  const double compass_per_s = counts.at(1) / 20.0;
  EXPECT_NEAR(compass_per_s, schedule.effective_rate_hz(NodeKind::kCompass), 0.1);
  for (int sonar = 2; sonar <= 9; ++sonar) EXPECT_NEAR(counts.at(sonar), counts.at(1), 2);
  EXPECT_NEAR(counts.at(10), 2 * counts.at(1), 2);
  double busy_s = 0.0;
  for (const Read& read : reads) {
    busy_s += schedule.transaction_s(read.node == 10 ? NodeKind::kLimitSwitch : NodeKind::kSonar);
  }
  EXPECT_NEAR(busy_s / 20.0, 0.8, 0.01);
}

TEST(ModbusPollSchedule, ALateReadKeepsTheGridAndMissedSlotsAreDropped) {
  PollScheduleOptions options;
  options.sonar_nodes = {2};
  ModbusPollSchedule schedule(options);
  ASSERT_EQ(schedule.next(0.0)->node, 1);
  schedule.record_success(1, 0.003);  // 3 ms late: the next read is still due at 0.1 s
  schedule.record_success(2, 0.003);
  schedule.record_success(10, 0.003);
  EXPECT_NEAR(schedule.next_due_s(), 0.05, 1e-9);  // the limit switch's
  EXPECT_EQ(schedule.next(0.05)->node, 10);
  schedule.record_success(10, 0.05);
  EXPECT_EQ(schedule.next(0.1)->node, 1);
  // The master stalls for a second: one read each, then back on the grid, no burst.
  const std::vector<int> expected = {1, 2, 10};
  for (const int node : expected) {
    const std::optional<PollTarget> target = schedule.next(1.234);
    ASSERT_TRUE(target);
    EXPECT_EQ(target->node, node);
    schedule.record_success(node, 1.234);
  }
  EXPECT_FALSE(schedule.next(1.234));
  EXPECT_NEAR(schedule.next_due_s(), 1.25, 1e-9);
}

TEST(ModbusPollSchedule, ANodeFailsAfterNFailuresInARowAndRecoversOnAGoodRead) {
  ModbusPollSchedule schedule{PollScheduleOptions{}};
  schedule.record_failure(3, {ReadError::kTimeout}, 0.0);
  schedule.record_failure(3, {ReadError::kTimeout}, 0.1);
  EXPECT_TRUE(schedule.health_of(3).ok);
  EXPECT_EQ(schedule.health_of(3).consecutive_failures, 2);
  schedule.record_failure(3, {ReadError::kTimeout}, 0.2);
  EXPECT_FALSE(schedule.health_of(3).ok);
  EXPECT_EQ(schedule.health_of(3).reason, "timeout");
  EXPECT_TRUE(schedule.health_of(4).ok);

  schedule.record_success(3, 0.3);
  const NodeHealth& health = schedule.health_of(3);
  EXPECT_TRUE(health.ok);
  EXPECT_EQ(health.reason, "");
  EXPECT_EQ(health.consecutive_failures, 0);
  EXPECT_EQ(health.reads, 4u);
  EXPECT_EQ(health.failures, 3u);
  EXPECT_EQ(health.timeouts, 3u);
}

TEST(ModbusPollSchedule, TheReasonIsTheLatestFailures) {
  ModbusPollSchedule schedule{PollScheduleOptions{}};
  schedule.record_failure(1, {ReadError::kTimeout}, 0.0);
  schedule.record_failure(1, {ReadError::kCrc}, 0.1);
  schedule.record_failure(1, {ReadError::kCrc}, 0.2);
  EXPECT_EQ(schedule.health_of(1).reason, "crc");
  EXPECT_EQ(schedule.health_of(1).crc_errors, 2u);
  schedule.record_failure(1, {ReadError::kException, 2}, 0.3);
  EXPECT_EQ(schedule.health_of(1).reason, "exception 2");
  EXPECT_EQ(schedule.health_of(1).exceptions, 1u);
  schedule.record_failure(1, {ReadError::kBadReply}, 0.4);
  EXPECT_EQ(schedule.health_of(1).reason, "bad reply");
}

TEST(ModbusPollSchedule, ANodeThatIsNotOkIsOnlyRetriedNowAndThen) {
  ModbusPollSchedule schedule{PollScheduleOptions{}};
  // Sonar 5 times out on every read; everybody else answers at once.
  std::map<int, int> counts;
  double now_s = 0.0;
  while (now_s < 10.0) {
    const std::optional<PollTarget> target = schedule.next(now_s);
    if (!target) {
      now_s = schedule.next_due_s();
      continue;
    }
    ++counts[target->node];
    if (target->node == 5) {
      schedule.record_failure(5, {ReadError::kTimeout}, now_s + 0.02);
      now_s += 0.02;
    } else {
      schedule.record_success(target->node, now_s);
    }
  }
  EXPECT_FALSE(schedule.health_of(5).ok);
  // Three tries at 10 Hz, then one every half second.
  EXPECT_NEAR(counts.at(5), 3 + 10.0 / 0.5, 2);
  EXPECT_NEAR(counts.at(4), 100, 1);
  EXPECT_NEAR(counts.at(10), 200, 1);
}

TEST(ModbusPollSchedule, ALostLinkMakesEveryNodeMissingUntilItAnswers) {
  ModbusPollSchedule schedule{PollScheduleOptions{}};
  schedule.link_lost();
  for (const NodeHealth& health : schedule.health()) {
    EXPECT_FALSE(health.ok);
    EXPECT_EQ(health.reason, "missing");
  }
  schedule.restart(5.0);
  EXPECT_FALSE(schedule.next(4.9));
  EXPECT_EQ(schedule.next(5.0)->node, 1);
  schedule.record_success(1, 5.0);
  EXPECT_TRUE(schedule.health_of(1).ok);
  EXPECT_FALSE(schedule.health_of(2).ok);
}

TEST(ModbusPollSchedule, RejectsABusItCannotPoll) {
  PollScheduleOptions repeated;
  repeated.compass_node = 2;
  EXPECT_THROW(ModbusPollSchedule{repeated}, std::invalid_argument);
  PollScheduleOptions broadcast;
  broadcast.limit_switch_node = 0;
  EXPECT_THROW(ModbusPollSchedule{broadcast}, std::invalid_argument);
  PollScheduleOptions no_rate;
  no_rate.sonar_rate_hz = 0.0;
  EXPECT_THROW(ModbusPollSchedule{no_rate}, std::invalid_argument);
  PollScheduleOptions no_sonar;
  no_sonar.sonar_nodes.clear();
  EXPECT_THROW(ModbusPollSchedule{no_sonar}, std::invalid_argument);
  ModbusPollSchedule schedule{PollScheduleOptions{}};
  EXPECT_THROW(schedule.health_of(42), std::out_of_range);
  EXPECT_THROW(schedule.record_success(42, 0.0), std::out_of_range);
}

}  // namespace
}  // namespace mobot::drivers::modbus
