#include "api/token_bucket.h"

#include <gtest/gtest.h>

namespace mobot::api {
namespace {

using namespace std::chrono_literals;

TEST(TokenBucket, ABurstThenTheRate) {
  const auto start = TokenBucket::Clock::time_point{} + 1h;
  TokenBucket bucket(10.0, 3.0, start);
  EXPECT_TRUE(bucket.take(start));
  EXPECT_TRUE(bucket.take(start));
  EXPECT_TRUE(bucket.take(start));
  EXPECT_FALSE(bucket.take(start)) << "the burst is spent";
  EXPECT_EQ(bucket.wait(start), std::chrono::duration_cast<TokenBucket::Clock::duration>(100ms));
  EXPECT_FALSE(bucket.take(start + 50ms));
  EXPECT_TRUE(bucket.take(start + 100ms));
  // A long pause refills no more than the burst.
  const auto later = start + 10s;
  int taken = 0;
  while (bucket.take(later)) ++taken;
  EXPECT_EQ(taken, 3);
  // Over a second at the rate: ten more.
  taken = 0;
  for (int ms = 1; ms <= 1000; ++ms) taken += bucket.take(later + std::chrono::milliseconds(ms));
  EXPECT_EQ(taken, 10);
}

TEST(TokenBucket, ATimeGoingBackwardsGivesNothing) {
  const auto start = TokenBucket::Clock::time_point{} + 1h;
  TokenBucket bucket(10.0, 1.0, start);
  EXPECT_TRUE(bucket.take(start));
  EXPECT_FALSE(bucket.take(start - 1s));
  EXPECT_FALSE(bucket.take(start + 50ms));
  EXPECT_TRUE(bucket.take(start + 100ms));
}

}  // namespace
}  // namespace mobot::api
