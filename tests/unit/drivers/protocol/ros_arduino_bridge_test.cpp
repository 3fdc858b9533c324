#include "drivers/protocol/ros_arduino_bridge.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace mobot::protocol::arduino_bridge {
namespace {

TEST(ArduinoBridge, CommandsEndInCarriageReturn) {
  EXPECT_EQ(command(kReadEncoders), "e\r");
  EXPECT_EQ(motor_speeds_command(12, -7), "m 12 -7\r");
  EXPECT_EQ(update_pid_command({20, 12, 0, 50}), "u 20:12:0:50\r");
  EXPECT_EQ(analog_read_command(3), "a 3\r");
}

TEST(ArduinoBridge, ParsesExactlyTheIntegersAsked) {
  EXPECT_EQ(parse_integers("123 -45", 2), (std::vector<long>{123, -45}));
  EXPECT_EQ(parse_integers("  7   8 ", 2), (std::vector<long>{7, 8}));
  EXPECT_FALSE(parse_integers("123", 2));
  EXPECT_FALSE(parse_integers("1 2 3", 2));
  EXPECT_FALSE(parse_integers("12a 3", 2));
  EXPECT_FALSE(parse_integers("Invalid Command", 1));
  EXPECT_FALSE(parse_integers("99999999999 1", 2));
  EXPECT_FALSE(parse_integers("", 1));
}

TEST(ArduinoBridge, WheelSpeedIsTicksPerThirtiethOfASecond) {
  // One wheel turn per second on a 1200-tick encoder: 40 ticks per 1/30 s frame.
  EXPECT_EQ(ticks_per_frame(2.0 * std::numbers::pi, 1200), 40);
  EXPECT_EQ(ticks_per_frame(-2.0 * std::numbers::pi, 1200), -40);
  EXPECT_NEAR(wheel_radps(40, 1200), 2.0 * std::numbers::pi, 1e-12);
  // 0.5 m/s on the Dashgo's 0.064 m wheels: 7.8125 rad/s, 49.7 ticks per frame.
  EXPECT_EQ(ticks_per_frame(0.5 / 0.064, 1200), 50);
  EXPECT_EQ(ticks_per_frame(std::nan(""), 1200), 0);
  EXPECT_EQ(ticks_per_frame(1e12, 1200), 30000);
}

TEST(EncoderUnwrap, CountsOnThroughThe16BitWrapBothWays) {
  EncoderUnwrap unwrap;
  EXPECT_EQ(unwrap.update(32000), 32000);
  EXPECT_EQ(unwrap.update(-32000), 33536);  // 32767 -> -32768 crossed going forward
  EXPECT_EQ(unwrap.update(32000), 32000);   // and back
  EXPECT_EQ(unwrap.update(-100), -100 + 0);
}

TEST(EncoderUnwrap, FollowsManyTurnsInSmallSteps) {
  EncoderUnwrap unwrap;
  std::int64_t truth = 0;
  unwrap.update(0);
  for (int i = 0; i < 10000; ++i) {
    truth += 37;
    const auto raw = static_cast<long>(static_cast<std::int16_t>(truth & 0xFFFF));
    ASSERT_EQ(unwrap.update(raw), truth);
  }
}

}  // namespace
}  // namespace mobot::protocol::arduino_bridge
