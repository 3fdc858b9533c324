// OperatorLock: a person (a token) holds the lock from any of their connections; another person is
// refused with the holder's label until the holder releases it, an admin takes it over, the stream
// it was last used on closes, or no command came for the dead-man time.
#include "api/operator_lock.h"

#include <gtest/gtest.h>

namespace mobot::api {
namespace {

using namespace std::chrono_literals;
using Clock = OperatorLock::Clock;

Claimant alice(std::uint64_t client_id = 1, bool stream = false) {
  return {Caller{7, Role::kOperator, "alice"}, client_id, stream, "10.0.0.2:5000"};
}
Claimant bob(std::uint64_t client_id = 2) {
  return {Caller{8, Role::kOperator, "bob"}, client_id, false, "10.0.0.3:5000"};
}
Claimant carol_admin(std::uint64_t client_id = 3) {
  return {Caller{9, Role::kAdmin, "carol"}, client_id, false, "10.0.0.4:5000"};
}

class OperatorLockTest : public ::testing::Test {
 protected:
  OperatorLock lock_;
  const Clock::time_point t0_ = Clock::now();
};

TEST_F(OperatorLockTest, AFreeLockGoesToTheFirstCommandAndRefusesAnotherPerson) {
  EXPECT_FALSE(lock_.holder(t0_).has_value());
  const auto held = lock_.command(alice(), t0_, 1000.0);
  ASSERT_TRUE(held.ok());
  EXPECT_EQ(held.value().claimant.caller.label, "alice");
  EXPECT_EQ(held.value().since_unix_s, 1000.0);
  const auto refused = lock_.command(bob(), t0_ + 1s, 1001.0);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().kind, ErrorKind::kConflict);
  EXPECT_EQ(refused.error().code, "operator_busy");
  EXPECT_NE(refused.error().message.find("alice"), std::string::npos) << refused.error().message;
  EXPECT_FALSE(lock_.acquire(bob(), t0_ + 1s, 1001.0).ok());
  EXPECT_EQ(lock_.holder(t0_ + 1s)->claimant.caller.label, "alice");
}

TEST_F(OperatorLockTest, TheSamePersonDrivesFromAnyConnectionAndTheLockFollows) {
  ASSERT_TRUE(lock_.acquire(alice(1), t0_, 1000.0).ok());
  const auto from_stream = lock_.command(alice(5, true), t0_ + 1s, 1001.0);
  ASSERT_TRUE(from_stream.ok());
  EXPECT_EQ(from_stream.value().claimant.client_id, 5U);
  EXPECT_EQ(from_stream.value().since_unix_s, 1000.0) << "held since the first acquire";
  // The REST connection it was taken on closes: nothing happens; the stream closes: it lapses.
  lock_.connection_closed(1);
  EXPECT_TRUE(lock_.holder(t0_ + 2s).has_value());
  lock_.connection_closed(5);
  EXPECT_FALSE(lock_.holder(t0_ + 2s).has_value());
  EXPECT_TRUE(lock_.command(bob(), t0_ + 2s, 1002.0).ok());
}

TEST_F(OperatorLockTest, OnlyTheHolderReleasesAndAnAdminTakesOver) {
  ASSERT_TRUE(lock_.acquire(alice(), t0_, 1000.0).ok());
  const auto not_holder = lock_.release(bob(), t0_);
  ASSERT_FALSE(not_holder.ok());
  EXPECT_EQ(not_holder.error().code, "not_holder");
  EXPECT_EQ(lock_.holder(t0_)->claimant.caller.label, "alice");
  const auto taken = lock_.take_over(carol_admin(), t0_ + 1s, 1001.0);
  ASSERT_TRUE(taken.ok());
  EXPECT_EQ(taken.value().claimant.caller.label, "carol");
  EXPECT_EQ(lock_.command(alice(), t0_ + 2s, 1002.0).error().code, "operator_busy");
  EXPECT_TRUE(lock_.release(carol_admin(), t0_ + 2s).ok());
  EXPECT_FALSE(lock_.holder(t0_ + 2s).has_value());
  EXPECT_TRUE(lock_.release(bob(), t0_ + 2s).ok()) << "releasing a free lock changes nothing";
  EXPECT_FALSE(lock_.holder(t0_ + 2s).has_value());
}

TEST_F(OperatorLockTest, TheDeadManLapsesTenSecondsAfterTheLastCommand) {
  ASSERT_TRUE(lock_.command(alice(), t0_, 1000.0).ok());
  ASSERT_TRUE(lock_.command(alice(), t0_ + 8s, 1008.0).ok());
  EXPECT_TRUE(lock_.holder(t0_ + 17s).has_value()) << "9 s after the last command";
  EXPECT_FALSE(lock_.command(bob(), t0_ + 17s, 1017.0).ok());
  EXPECT_FALSE(lock_.holder(t0_ + 18s + 1ms).has_value());
  const auto bobs = lock_.command(bob(), t0_ + 19s, 1019.0);
  ASSERT_TRUE(bobs.ok());
  EXPECT_EQ(bobs.value().since_unix_s, 1019.0);
}

TEST_F(OperatorLockTest, AClaimTheRobotRefusedIsUndoneUnlessTheLockMovedOn) {
  const auto taken = lock_.claim(alice(1), t0_, 1000.0);
  ASSERT_TRUE(taken.ok());
  lock_.undo(taken.value());
  EXPECT_FALSE(lock_.holder(t0_).has_value()) << "a free lock is free again";
  ASSERT_TRUE(lock_.command(alice(1), t0_, 1000.0).ok());
  const auto moved = lock_.claim(alice(5, true), t0_ + 1s, 1001.0);
  ASSERT_TRUE(moved.ok());
  lock_.undo(moved.value());
  EXPECT_EQ(lock_.holder(t0_ + 1s)->claimant.client_id, 1U) << "back on the connection it was on";
  // Once the lock has changed hands, an old claim's undo does nothing.
  const auto stale = lock_.claim(alice(1), t0_ + 2s, 1002.0);
  ASSERT_TRUE(lock_.take_over(carol_admin(), t0_ + 3s, 1003.0).ok());
  lock_.undo(stale.value());
  EXPECT_EQ(lock_.holder(t0_ + 3s)->claimant.caller.label, "carol");
}

}  // namespace
}  // namespace mobot::api
