#include "core/control/command_mux.h"

#include <gtest/gtest.h>

namespace mobot::control {
namespace {

CommandMux make_mux() {
  return CommandMux({{"navigation", 5, 1.0}, {"teleop", 7, 1.0}, {"safety", 10, 0.2}});
}

TEST(CommandMux, SilentMuxStops) {
  const CommandMux mux = make_mux();
  const auto selection = mux.select(0.0);
  EXPECT_FALSE(selection.source.has_value());
  EXPECT_EQ(selection.command, msgs::Twist{});
}

TEST(CommandMux, HigherPriorityWinsUntilItTimesOut) {
  CommandMux mux = make_mux();
  ASSERT_TRUE(mux.submit("navigation", {0.5, 0.0}, 0.0));
  ASSERT_TRUE(mux.submit("teleop", {0.2, 0.1}, 0.0, 0.3));
  EXPECT_EQ(mux.select(0.1).source, "teleop");
  EXPECT_EQ(mux.select(0.1).command, (msgs::Twist{0.2, 0.1}));
  EXPECT_EQ(mux.select(0.35).source, "navigation");
  EXPECT_FALSE(mux.select(1.5).source.has_value());
}

TEST(CommandMux, TtlIsTheDeadMan) {
  CommandMux mux = make_mux();
  mux.submit("teleop", {1.0, 0.0}, 10.0, 0.05);
  EXPECT_TRUE(mux.is_active("teleop", 10.04));
  EXPECT_FALSE(mux.is_active("teleop", 10.05));
}

TEST(CommandMux, UnknownSourceIsRefused) {
  CommandMux mux = make_mux();
  EXPECT_FALSE(mux.submit("joystick", {1.0, 0.0}, 0.0));
  EXPECT_FALSE(mux.select(0.0).source.has_value());
}

TEST(CommandMux, ClearSilencesASource) {
  CommandMux mux = make_mux();
  mux.submit("safety", {}, 0.0);
  mux.submit("teleop", {0.3, 0.0}, 0.0);
  EXPECT_EQ(mux.select(0.1).source, "safety");
  mux.clear("safety");
  EXPECT_EQ(mux.select(0.1).source, "teleop");
}

TEST(CommandMux, DuplicateSourceNamesAreRejected) {
  EXPECT_THROW(CommandMux({{"a", 1, 1.0}, {"a", 2, 1.0}}), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::control
