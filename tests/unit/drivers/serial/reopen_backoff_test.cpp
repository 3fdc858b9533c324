#include "drivers/serial/reopen_backoff.h"

#include <gtest/gtest.h>

namespace mobot::drivers::serial {
namespace {

TEST(ReopenBackoff, DoublesUpToTheCapAndStartsAgainAfterReset) {
  ReopenBackoff backoff({.first_delay_s = 0.1, .factor = 2.0, .max_delay_s = 0.5});
  EXPECT_DOUBLE_EQ(backoff.next_delay_s(), 0.1);
  EXPECT_DOUBLE_EQ(backoff.next_delay_s(), 0.2);
  EXPECT_DOUBLE_EQ(backoff.next_delay_s(), 0.4);
  EXPECT_DOUBLE_EQ(backoff.next_delay_s(), 0.5);
  EXPECT_DOUBLE_EQ(backoff.next_delay_s(), 0.5);
  backoff.reset();
  EXPECT_DOUBLE_EQ(backoff.next_delay_s(), 0.1);
}

}  // namespace
}  // namespace mobot::drivers::serial
