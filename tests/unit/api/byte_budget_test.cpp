#include "api/byte_budget.h"

#include <gtest/gtest.h>

namespace mobot::api {
namespace {

using namespace std::chrono_literals;

const auto kStart = ByteBudget::Clock::time_point{} + 1h;

TEST(ByteBudget, WithoutACapEverythingGoes) {
  ByteBudget budget;
  EXPECT_FALSE(budget.capped());
  EXPECT_TRUE(budget.take(10'000'000, TopicPriority::kBulk, kStart));
}

TEST(ByteBudget, TheStateAlwaysGoesAndTheSensorsWaitForItsDebt) {
  ByteBudget budget;
  budget.set_rate(100'000.0, kStart);  // burst 50 000 bytes
  // The state takes the burst and more: it is never held back.
  for (int i = 0; i < 6; ++i) EXPECT_TRUE(budget.take(10'000, TopicPriority::kState, kStart));
  // 10 000 bytes in debt: a 1000-byte scan waits for 110 ms of refill.
  EXPECT_FALSE(budget.take(1'000, TopicPriority::kSensor, kStart));
  EXPECT_FALSE(budget.take(1'000, TopicPriority::kSensor, kStart + 100ms));
  EXPECT_TRUE(budget.take(1'000, TopicPriority::kSensor, kStart + 111ms));
}

TEST(ByteBudget, BulkLeavesHalfTheBurstToTheSensors) {
  ByteBudget budget;
  budget.set_rate(100'000.0, kStart);  // burst 50 000
  EXPECT_TRUE(budget.take(20'000, TopicPriority::kBulk, kStart));   // 50 000 >= 20 000 + 25 000
  EXPECT_FALSE(budget.take(10'000, TopicPriority::kBulk, kStart));  // 30 000 < 35 000
  EXPECT_TRUE(budget.take(25'000, TopicPriority::kSensor, kStart));
  // Over a second at the rate, with frames of 10 000 bytes: about ten go in all.
  int taken = 0;
  for (int ms = 1; ms <= 1000; ++ms) {
    taken += budget.take(10'000, TopicPriority::kSensor, kStart + std::chrono::milliseconds(ms));
  }
  EXPECT_GE(taken, 9);
  EXPECT_LE(taken, 11);
}

TEST(ByteBudget, AVeryThinCapStillLetsOneLargeFrameThrough) {
  ByteBudget budget;
  budget.set_rate(1'000.0, kStart);  // 8 kbit/s: the burst is the 16 KiB floor
  EXPECT_TRUE(budget.take(12'000, TopicPriority::kSensor, kStart));
  EXPECT_FALSE(budget.take(12'000, TopicPriority::kSensor, kStart + 1s));
}

}  // namespace
}  // namespace mobot::api
