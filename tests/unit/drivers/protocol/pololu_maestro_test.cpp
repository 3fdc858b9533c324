#include "drivers/protocol/pololu_maestro.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

namespace mobot::protocol::maestro {
namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

// Feeds every byte to the parser and collects what it made of them.
std::vector<CommandEvent> parse_all(CommandParser& parser, const Bytes& bytes) {
  std::vector<CommandEvent> events;
  for (std::uint8_t byte : bytes) {
    if (auto event = parser.feed(byte)) events.push_back(*event);
  }
  return events;
}

// Every expected packet below is an example of the Maestro Servo Controller User's Guide
// (sections 5.c-5.e), byte for byte.
TEST(MaestroCommands, MatchTheUsersGuide) {
  // Set Target of servo 0 (5.c) and channel 2 (5.e) to 1500 us: 6000 quarter-us.
  EXPECT_EQ(set_target(0, 6000), (Bytes{0x84, 0x00, 0x70, 0x2E}));
  EXPECT_EQ(set_target(2, 6000), (Bytes{0x84, 0x02, 0x70, 0x2E}));
  // Set Speed of channel 5 to 140 (3.5 us/ms).
  EXPECT_EQ(set_speed(5, 140), (Bytes{0x87, 0x05, 0x0C, 0x01}));
  // Set Multiple Targets: channel 3 to 0 (off), channel 4 to 6000.
  const std::vector<std::uint16_t> targets{0, 6000};
  EXPECT_EQ(set_multiple_targets(3, targets), (Bytes{0x9F, 0x02, 0x03, 0x00, 0x00, 0x70, 0x2E}));
  // The queries and Go Home: command byte, and the channel for Get Position.
  EXPECT_EQ(get_position(1), (Bytes{0x90, 0x01}));
  EXPECT_EQ(get_moving_state(), (Bytes{0x93}));
  EXPECT_EQ(get_errors(), (Bytes{0xA1}));
  EXPECT_EQ(go_home(), (Bytes{0xA2}));
  EXPECT_EQ(set_acceleration(1, 4), (Bytes{0x89, 0x01, 0x04, 0x00}));
}

TEST(MaestroCommands, ValuesBeyondFourteenBitsAreClamped) {
  EXPECT_EQ(set_target(0, 20000), (Bytes{0x84, 0x00, 0x7F, 0x7F}));
  EXPECT_EQ(set_speed(1, 0x3FFF), (Bytes{0x87, 0x01, 0x7F, 0x7F}));
  // A channel is a data byte: its top bit is never set.
  EXPECT_EQ(get_position(0x85), (Bytes{0x90, 0x05}));
}

TEST(MaestroCrc7, MatchesTheUsersGuideAndTheMotoronsExample) {
  // 5.d: 0x83, 0x01 gets the CRC byte 0x17.
  EXPECT_EQ(crc7(Bytes{0x83, 0x01}), 0x17);
  EXPECT_EQ(with_crc(Bytes{0x83, 0x01}), (Bytes{0x83, 0x01, 0x17}));
  // The same CRC-7 on the Motoron (Pololu 0J84, section 10): Set Speed 1 to 100 ends with 0x68.
  EXPECT_EQ(crc7(Bytes{0xD1, 0x01, 0x64, 0x00}), 0x68);
  EXPECT_EQ(crc7(Bytes{}), 0x00);
  // Always a data byte.
  for (int byte = 0; byte < 256; ++byte) {
    EXPECT_LT(crc7(Bytes{static_cast<std::uint8_t>(byte), 0x42}), 0x80) << byte;
  }
}

TEST(MaestroReplies, AreLittleEndianInTheOrderAsked) {
  const std::vector<Query> queries{Query::kPosition, Query::kPosition, Query::kMovingState,
                                   Query::kErrors};
  EXPECT_EQ(reply_bytes(queries), 7U);
  // 6000 (0x1770), 4000 (0x0FA0), moving, errors 0x0110 (serial protocol, script PC).
  const auto values = decode_replies(queries, Bytes{0x70, 0x17, 0xA0, 0x0F, 0x01, 0x10, 0x01});
  ASSERT_TRUE(values);
  EXPECT_EQ(*values, (std::vector<std::uint16_t>{6000, 4000, 1, 0x0110}));
  // A byte more or less: the answers cannot be told apart.
  EXPECT_FALSE(decode_replies(queries, Bytes{0x70, 0x17, 0xA0, 0x0F, 0x01, 0x10}));
  EXPECT_FALSE(decode_replies(queries, Bytes{0x70, 0x17, 0xA0, 0x0F, 0x01, 0x10, 0x01, 0x00}));
}

TEST(MaestroReplyCollector, CompletesFromChunksAndRefusesAnOverrun) {
  ReplyCollector collector;
  collector.expect({Query::kPosition, Query::kErrors});
  EXPECT_EQ(collector.feed(Bytes{0x70}), ReplyCollector::State::kWaiting);
  EXPECT_FALSE(collector.values());
  EXPECT_EQ(collector.feed(Bytes{0x17, 0x00}), ReplyCollector::State::kWaiting);
  EXPECT_EQ(collector.feed(Bytes{0x00}), ReplyCollector::State::kComplete);
  EXPECT_EQ(*collector.values(), (std::vector<std::uint16_t>{6000, 0}));
  // A byte after the answers: noise or a late answer, so the batch is not trusted.
  EXPECT_EQ(collector.feed(Bytes{0x00}), ReplyCollector::State::kOverrun);
  EXPECT_FALSE(collector.values());

  collector.expect({Query::kPosition});
  EXPECT_EQ(collector.feed(Bytes{0x70, 0x17, 0x55}), ReplyCollector::State::kOverrun);
  collector.expect({Query::kPosition});
  collector.cancel();
  EXPECT_EQ(collector.feed(Bytes{0x01}), ReplyCollector::State::kOverrun);
  EXPECT_EQ(collector.counters().bytes, 9U);
  // The second batch came whole before its extra byte, however the bytes were cut.
  EXPECT_EQ(collector.counters().batches, 2U);
  EXPECT_EQ(collector.counters().overruns, 3U);
  EXPECT_EQ(collector.counters().abandoned, 1U);
}

TEST(MaestroPlausibility, RefusesWhatTheMaestroCannotSend) {
  EXPECT_TRUE(plausible_servo_position(0));      // off
  EXPECT_TRUE(plausible_servo_position(256));    // 64 us
  EXPECT_TRUE(plausible_servo_position(16320));  // 4080 us
  EXPECT_FALSE(plausible_servo_position(255));
  EXPECT_FALSE(plausible_servo_position(16321));
  EXPECT_TRUE(plausible_analog(1023));
  EXPECT_FALSE(plausible_analog(1024));
  EXPECT_TRUE(plausible_errors(0x01FF));
  EXPECT_FALSE(plausible_errors(0x0200));
  EXPECT_TRUE(plausible_moving_state(1));
  EXPECT_FALSE(plausible_moving_state(2));
  EXPECT_EQ(error_names(0), "none");
  EXPECT_EQ(error_names(error_bit::kSerialProtocol | error_bit::kSerialCrc),
            "serial_crc|serial_protocol");
  EXPECT_EQ(error_names(0x8000), "bit15");
}

TEST(MaestroCommandParser, ReadsWhatTheBuildersMake) {
  CommandParser parser;
  Bytes stream;
  for (const Bytes& command : {set_target(0, 6000), set_speed(5, 140), set_acceleration(1, 4),
                               get_position(2), get_moving_state(), get_errors(), go_home()}) {
    stream.insert(stream.end(), command.begin(), command.end());
  }
  const std::vector<std::uint16_t> targets{0, 6000};
  const Bytes multiple = set_multiple_targets(3, targets);
  stream.insert(stream.end(), multiple.begin(), multiple.end());
  const std::vector<CommandEvent> events = parse_all(parser, stream);
  ASSERT_EQ(events.size(), 8U);
  for (const CommandEvent& event : events) {
    EXPECT_EQ(event.errors, 0);
    ASSERT_TRUE(event.command);
  }
  EXPECT_EQ(*events[0].command, (ParsedCommand{Command::kSetTarget, 0, 6000, {}}));
  EXPECT_EQ(*events[1].command, (ParsedCommand{Command::kSetSpeed, 5, 140, {}}));
  EXPECT_EQ(*events[2].command, (ParsedCommand{Command::kSetAcceleration, 1, 4, {}}));
  EXPECT_EQ(*events[3].command, (ParsedCommand{Command::kGetPosition, 2, 0, {}}));
  EXPECT_EQ(events[4].command->command, Command::kGetMovingState);
  EXPECT_EQ(events[5].command->command, Command::kGetErrors);
  EXPECT_EQ(events[6].command->command, Command::kGoHome);
  EXPECT_EQ(*events[7].command, (ParsedCommand{Command::kSetMultipleTargets, 3, 0, {0, 6000}}));
  EXPECT_EQ(parser.pending_bytes(), 0U);
}

TEST(MaestroCommandParser, FlagsProtocolErrors) {
  CommandParser parser;
  // An unknown command byte, a data byte outside a command.
  std::vector<CommandEvent> events = parse_all(parser, Bytes{0x80, 0x12});
  ASSERT_EQ(events.size(), 2U);
  EXPECT_EQ(events[0].errors, error_bit::kSerialProtocol);
  EXPECT_EQ(events[1].errors, error_bit::kSerialProtocol);
  // A command cut short by the next: the next one still counts.
  events = parse_all(parser, Bytes{0x84, 0x00, 0x70, 0x90, 0x01});
  ASSERT_EQ(events.size(), 2U);
  EXPECT_EQ(events[0].errors, error_bit::kSerialProtocol);
  EXPECT_FALSE(events[0].command);
  EXPECT_EQ(*events[1].command, (ParsedCommand{Command::kGetPosition, 1, 0, {}}));
  // ... also one without data bytes, which completes with its error.
  events = parse_all(parser, Bytes{0x84, 0x00, 0xA1});
  ASSERT_EQ(events.size(), 1U);
  EXPECT_EQ(events[0].errors, error_bit::kSerialProtocol);
  EXPECT_EQ(events[0].command->command, Command::kGetErrors);
  // Set Multiple Targets of no channel.
  events = parse_all(parser, Bytes{0x9F, 0x00});
  ASSERT_EQ(events.size(), 1U);
  EXPECT_EQ(events[0].errors, error_bit::kSerialProtocol);
}

TEST(MaestroCommandParser, WithCrcTakesOnlyCommandsWithTheirCrc) {
  CommandParser parser(/*crc=*/true);
  std::vector<CommandEvent> events = parse_all(parser, with_crc(set_target(1, 7000)));
  ASSERT_EQ(events.size(), 1U);
  EXPECT_EQ(*events[0].command, (ParsedCommand{Command::kSetTarget, 1, 7000, {}}));
  // Get Errors waits for its CRC byte.
  EXPECT_TRUE(parse_all(parser, get_errors()).empty());
  events = parse_all(parser, Bytes{static_cast<std::uint8_t>(crc7(get_errors()) ^ 0x01)});
  ASSERT_EQ(events.size(), 1U);
  EXPECT_EQ(events[0].errors, error_bit::kSerialCrc);
  EXPECT_FALSE(events[0].command);
}

TEST(MaestroCalibration, MapsAnglesToPulsesAndBack) {
  const ServoCalibration servo;  // 1500 us at 0, 1000 us per 90 deg
  EXPECT_DOUBLE_EQ(pulse_us_for_angle(servo, 0.0), 1500.0);
  EXPECT_EQ(target_for_angle(servo, 0.0), 6000);
  EXPECT_EQ(target_for_angle(servo, 90.0 * kRadPerDeg), 10000);  // 2500 us
  EXPECT_EQ(target_for_angle(servo, -45.0 * kRadPerDeg), 4000);  // 1000 us
  EXPECT_NEAR(*angle_for_position(servo, 10000), 90.0 * kRadPerDeg, 1e-12);
  // A mirrored servo: the larger pulse turns the joint the negative way.
  const ServoCalibration mirrored{1450.0, 800.0, -1};
  EXPECT_EQ(target_for_angle(mirrored, 0.5), 4200);  // 1450 - 400 us
  EXPECT_NEAR(*angle_for_position(mirrored, 4200), 0.5, 1e-12);
  // Off: the Maestro does not know where the servo is.
  EXPECT_FALSE(angle_for_position(servo, 0));
  // Never 0 (off), never past 14 bits; a non-finite angle is the centre.
  EXPECT_EQ(target_for_angle(servo, -10.0), 1);
  EXPECT_EQ(target_for_angle(servo, 100.0), 0x3FFF);
  EXPECT_EQ(target_for_angle(servo, std::numeric_limits<double>::quiet_NaN()), 6000);
}

TEST(MaestroCalibration, SpeedAndAccelerationInTheMaestrosUnits) {
  const ServoCalibration servo;
  // 2 rad/s: 1273.2 us/s, 50.9 x (0.25 us / 10 ms); rounded down to stay within the rate.
  EXPECT_EQ(speed_for_rate(servo, 2.0), 50);
  EXPECT_LE(rate_for_speed(servo, 50), 2.0);
  EXPECT_NEAR(rate_for_speed(servo, 50), 1.9635, 1e-4);
  EXPECT_EQ(speed_for_rate(servo, 0.0), 0);  // unlimited
  EXPECT_EQ(speed_for_rate(servo, 1e-6), 1);
  EXPECT_EQ(speed_for_rate(servo, std::numeric_limits<double>::infinity()), 0);
  // The guide: acceleration 4 changes the speed by at most 1250 us/s every second.
  EXPECT_EQ(acceleration_for(servo, 1250.0 / servo.us_per_rad), 4);
  EXPECT_EQ(acceleration_for(servo, 0.0), 0);
  EXPECT_EQ(acceleration_for(servo, 1e6), 255);
}

TEST(MaestroRanger, ScalesTheLvEzsVoltage) {
  const RangerScale lv_ez;  // VCC/512 per inch at 5 V, nothing from 6 m on
  // 100 inches: 0.977 V, 199.8 of 1023.
  EXPECT_NEAR(analog_volts(200), 0.9775, 1e-4);
  EXPECT_NEAR(*range_from_analog(200, lv_ez), 2.54, 0.0127);
  EXPECT_NEAR(*range_from_analog(0, lv_ez), 0.0, 1e-12);
  // 254 inches (no echo) is 6.45 m: beyond range_max_m.
  EXPECT_FALSE(range_from_analog(508, lv_ez));
  EXPECT_FALSE(range_from_analog(1023, lv_ez));
  EXPECT_FALSE(range_from_analog(1024, lv_ez));
  // Powered at 3.3 V: 3.3/512 V per inch, read against the Maestro's 5 V: 3.94 m per volt.
  const RangerScale at_3v3{512.0 * 0.0254 / 3.3, 6.0};
  EXPECT_NEAR(*range_from_analog(132, at_3v3), 2.54, 0.02);
}

}  // namespace
}  // namespace mobot::protocol::maestro
