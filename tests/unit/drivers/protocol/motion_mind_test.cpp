#include "drivers/protocol/motion_mind.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

namespace mobot::protocol::motion_mind {
namespace {

using Bytes = std::vector<std::uint8_t>;

// Feeds `bytes` one at a time, collecting every reply.
std::vector<Reply> feed_bytewise(ReplyParser& parser, const Bytes& bytes) {
  std::vector<Reply> replies;
  for (std::uint8_t byte : bytes) {
    std::optional<Reply> reply = parser.feed(std::span<const std::uint8_t>(&byte, 1));
    if (reply) replies.push_back(*reply);
  }
  return replies;
}

TEST(MotionMindChecksum, IsTheLowByteOfTheSum) {
  // The data sheet's example: bytes summing to 1256 (0x4E8) give 0xE8.
  EXPECT_EQ(checksum(Bytes{0xFF, 0xFF, 0xFF, 0xFF, 0xEC}), 0xE8);
  EXPECT_EQ(checksum(Bytes{}), 0x00);
}

// Every expected packet below is a binary example of the data sheet (section 5), byte for byte.
TEST(MotionMindCommands, MotionCommandsMatchTheDataSheet) {
  // MOVETO_ABSOLUTE -10000: command 21, address 1, 0xFFFFD8F0 LSB first, checksum 988 & 0xFF.
  EXPECT_EQ(move_to_absolute(1, -10000), (Bytes{0x15, 0x01, 0xF0, 0xD8, 0xFF, 0xFF, 0xDC}));
  // MOVETO_ABSOLUTE -100046 (0xFFFE7932).
  EXPECT_EQ(move_to_absolute(1, -100046), (Bytes{0x15, 0x01, 0x32, 0x79, 0xFE, 0xFF, 0xBE}));
  // MOVETO_RELATIVE +100000 (0x000186A0).
  EXPECT_EQ(move_to_relative(1, 100000), (Bytes{0x16, 0x01, 0xA0, 0x86, 0x01, 0x00, 0x3E}));
  // MOVEAT_VELOCITY -200 counts per period (0xFF38).
  EXPECT_EQ(move_at_velocity(1, -200), (Bytes{0x17, 0x01, 0x38, 0xFF, 0x4F}));
  // CHANGE_SPEED +763 (0x02FB) and +128.
  EXPECT_EQ(change_speed(1, 763), (Bytes{0x14, 0x01, 0xFB, 0x02, 0x12}));
  EXPECT_EQ(change_speed(1, 128), (Bytes{0x14, 0x01, 0x80, 0x00, 0x95}));
  // RESTORE and RESET: command, address, checksum.
  EXPECT_EQ(restore_defaults(1), (Bytes{0x1B, 0x01, 0x1C}));
  EXPECT_EQ(reset(1), (Bytes{0x1C, 0x01, 0x1D}));
  // R1's right wheel (address 2) at 1 rad/s: 30 counts per period, 23 + 2 + 30 = 0x37.
  EXPECT_EQ(move_at_velocity(2, velocity_setpoint(1.0, kR1WheelCountsPerRev)),
            (Bytes{0x17, 0x02, 0x1E, 0x00, 0x37}));
}

TEST(MotionMindCommands, RegisterCommandsMatchTheDataSheet) {
  // WRITE (24) register 0 POSITION, 4 bytes of -10000.
  EXPECT_EQ(write_register(1, Register::kPosition, -10000),
            (Bytes{0x18, 0x01, 0x00, 0xF0, 0xD8, 0xFF, 0xFF, 0xDF}));
  // WRITE register 1 VELOCITYLIMIT, 2 bytes of 100.
  EXPECT_EQ(write_register(1, Register::kVelocityLimit, 100),
            (Bytes{0x18, 0x01, 0x01, 0x64, 0x00, 0x7E}));
  // WRITE register 2 VELOCITYFF, 1 byte of 128.
  EXPECT_EQ(write_register(1, Register::kVelocityFf, 128), (Bytes{0x18, 0x01, 0x02, 0x80, 0x9B}));
  // WRITE_STORE (25): the same with the command byte one higher.
  EXPECT_EQ(write_store_register(1, Register::kPosition, -10000),
            (Bytes{0x19, 0x01, 0x00, 0xF0, 0xD8, 0xFF, 0xFF, 0xE0}));
  EXPECT_EQ(write_store_register(1, Register::kVelocityLimit, 100),
            (Bytes{0x19, 0x01, 0x01, 0x64, 0x00, 0x7F}));
  EXPECT_EQ(write_store_register(1, Register::kVelocityFf, 128),
            (Bytes{0x19, 0x01, 0x02, 0x80, 0x9C}));
  // READ (26) of POSITION: mask 0x00000001 LSB first.
  EXPECT_EQ(read_registers(1, mask_of(Register::kPosition)),
            (Bytes{0x1A, 0x01, 0x01, 0x00, 0x00, 0x00, 0x1C}));
  // READ of registers 2, 8, 19 and 20: mask bytes 0x04, 0x01, 0x18, 0x00, checksum 56.
  const RegisterMask mask = mask_of(Register::kVelocityFf) | mask_of(Register::kPidScalar) |
                            mask_of(Register::kAnalogCon) | mask_of(Register::kAnalogFbck);
  EXPECT_EQ(read_registers(1, mask), (Bytes{0x1A, 0x01, 0x04, 0x01, 0x18, 0x00, 0x38}));
  // READ_REGISTER (29) of POSITION and of VELOCITYLIMIT.
  EXPECT_EQ(read_register(1, Register::kPosition), (Bytes{0x1D, 0x01, 0x00, 0x1E}));
  EXPECT_EQ(read_register(1, Register::kVelocityLimit), (Bytes{0x1D, 0x01, 0x01, 0x1F}));
}

TEST(MotionMindCommands, ValuesAreClampedToTheirField) {
  EXPECT_EQ(parse_command(change_speed(1, 5000))->value, 1023);
  EXPECT_EQ(parse_command(change_speed(1, -5000))->value, -1023);
  EXPECT_EQ(parse_command(move_at_velocity(1, 40000))->value, 32767);
  EXPECT_EQ(parse_command(move_at_velocity(1, -40000))->value, -32768);
  EXPECT_EQ(parse_command(write_register(1, Register::kVelocityLimit, 0))->value, 1);
  EXPECT_EQ(parse_command(write_register(1, Register::kPTerm, 70000))->value, 65535);
}

TEST(MotionMindCommands, ABoardParsesWhatTheHostBuilds) {
  const auto absolute = parse_command(move_to_absolute(7, -123456));
  ASSERT_TRUE(absolute);
  EXPECT_EQ(absolute->command, Command::kMoveToAbsolute);
  EXPECT_EQ(absolute->address, 7);
  EXPECT_EQ(absolute->value, -123456);

  const auto write = parse_command(write_register(3, Register::kVnLimit, -100000));
  ASSERT_TRUE(write);
  EXPECT_EQ(write->command, Command::kWrite);
  EXPECT_EQ(write->reg, Register::kVnLimit);
  EXPECT_EQ(write->value, -100000);

  // FUNCTION is unsigned: 0xFFFF stays 65535.
  EXPECT_EQ(parse_command(write_register(1, Register::kFunction, 0xFFFF))->value, 65535);

  const auto read = parse_command(read_registers(2, 0xFFFFFFFFu));
  ASSERT_TRUE(read);
  EXPECT_EQ(read->mask, 0xFFFFFFFFu);

  const auto read_one = parse_command(read_register(2, Register::kStatus));
  ASSERT_TRUE(read_one);
  EXPECT_EQ(read_one->reg, Register::kStatus);
  EXPECT_EQ(parse_command(reset(99))->address, kBroadcastAddress);
}

TEST(MotionMindCommands, ABoardRejectsBadBytes) {
  Bytes bad_checksum = move_at_velocity(1, 10);
  bad_checksum.back() ^= 0x01;
  EXPECT_FALSE(parse_command(bad_checksum));
  Bytes too_long = move_at_velocity(1, 10);
  too_long.push_back(0x00);
  EXPECT_FALSE(parse_command(too_long));
  Bytes two_commands = move_at_velocity(1, 10);
  const Bytes second = move_at_velocity(2, 10);
  two_commands.insert(two_commands.end(), second.begin(), second.end());
  EXPECT_FALSE(parse_command(two_commands));
  EXPECT_FALSE(parse_command(Bytes{0x13, 0x01, 0x14}));        // unknown command 19
  EXPECT_FALSE(parse_command(Bytes{0x1D, 0x01, 0x20, 0x3E}));  // register 32 does not exist
  EXPECT_FALSE(parse_command(Bytes{0x1B, 0x01}));
  // A WRITE's length follows from its register: 2 bytes of data for a 4-byte register is short.
  EXPECT_FALSE(parse_command(Bytes{0x18, 0x01, 0x00, 0x10, 0x00, 0x29}));
}

TEST(MotionMindReplies, ShapesFollowTheRegistersAskedFor) {
  EXPECT_EQ(read_data_bytes(mask_of(Register::kPosition) | mask_of(Register::kStatus)), 6u);
  EXPECT_EQ(reply_bytes(read_reply(1, mask_of(Register::kPosition) | mask_of(Register::kStatus))),
            8u);
  EXPECT_EQ(read_data_bytes(0xFFFFFFFFu), 70u);
  EXPECT_TRUE(motion_reply(1, 0).ack);
  EXPECT_EQ(motion_reply(1, function_bit::kRetPos).data_bytes, 4u);
  EXPECT_EQ(
      motion_data_bytes(function_bit::kRetPos | function_bit::kRetVel | function_bit::kRetTime),
      10u);
  EXPECT_EQ(read_register_reply(4, Register::kStatus).data_bytes, 2u);
}

TEST(MotionMindReplies, ReadReplyOfTheDataSheet) {
  // READ of POSITION holding 20000: address 1, 0x00004E20 LSB first, 1 + 32 + 78 = 111.
  const Bytes wire{0x01, 0x20, 0x4E, 0x00, 0x00, 0x6F};
  EXPECT_EQ(encode_data_reply(1, Bytes{0x20, 0x4E, 0x00, 0x00}), wire);
  ReplyParser parser;
  parser.expect(read_reply(1, mask_of(Register::kPosition)));
  const std::optional<Reply> reply = parser.feed(wire);
  ASSERT_TRUE(reply);
  EXPECT_FALSE(reply->ack);
  EXPECT_EQ(reply->address, 1);
  EXPECT_EQ(register_value(mask_of(Register::kPosition), Register::kPosition, reply->data), 20000);
  EXPECT_FALSE(parser.awaiting());
  EXPECT_EQ(parser.counters().replies, 1u);
  EXPECT_EQ(parser.counters().discarded_bytes, 0u);
}

TEST(MotionMindReplies, ReadRegisterReplyOfTheDataSheet) {
  // VELOCITYLIMIT holding 1023: 1, 0xFF, 0x03, checksum 259 & 0xFF = 3.
  ReplyParser parser;
  parser.expect(read_register_reply(1, Register::kVelocityLimit));
  const auto reply = parser.feed(Bytes{0x01, 0xFF, 0x03, 0x03});
  ASSERT_TRUE(reply);
  EXPECT_EQ(
      register_value(mask_of(Register::kVelocityLimit), Register::kVelocityLimit, reply->data),
      1023);
}

TEST(MotionMindReplies, MotionReplyCarriesThePosition) {
  // The data sheet's MOVETO_ABSOLUTE answer under RETPOS: address 1, POSITION 1000, 0xEC.
  ReplyParser parser;
  parser.expect(motion_reply(1, function_bit::kRetPos));
  const auto reply = parser.feed(Bytes{0x01, 0xE8, 0x03, 0x00, 0x00, 0xEC});
  ASSERT_TRUE(reply);
  const auto feedback = decode_motion_reply(function_bit::kRetPos, reply->data);
  ASSERT_TRUE(feedback);
  EXPECT_EQ(feedback->position_counts, 1000);
  EXPECT_FALSE(feedback->velocity_counts_per_period);
  EXPECT_FALSE(feedback->time_periods);

  const std::uint16_t all = function_bit::kRetPos | function_bit::kRetVel | function_bit::kRetTime;
  const Bytes data{0xFF, 0xFF, 0xFF, 0xFF, 0x38, 0xFF, 0x10, 0x00, 0x00, 0x80};
  const auto full = decode_motion_reply(all, data);
  ASSERT_TRUE(full);
  EXPECT_EQ(full->position_counts, -1);
  EXPECT_EQ(full->velocity_counts_per_period, -200);
  EXPECT_EQ(full->time_periods, 0x80000010u);
  EXPECT_FALSE(decode_motion_reply(all, Bytes{0x00}));
}

TEST(MotionMindReplies, SeveralRegistersComeInIndexOrder) {
  // POSITION -2 then STATUS with NEGLIMIT and INPOSITION.
  const RegisterMask mask = mask_of(Register::kPosition) | mask_of(Register::kStatus);
  const Bytes data{0xFE, 0xFF, 0xFF, 0xFF, 0x01, 0x02};
  EXPECT_EQ(register_value(mask, Register::kPosition, data), -2);
  EXPECT_EQ(register_value(mask, Register::kStatus, data), 0x0201);
  EXPECT_FALSE(register_value(mask, Register::kVelocity, data));
  EXPECT_FALSE(register_value(mask, Register::kStatus, Bytes{0x00, 0x00, 0x00, 0x00, 0x01}));
}

TEST(MotionMindReplyParser, SplitReadsOneByteAtATime) {
  ReplyParser parser;
  parser.expect(motion_reply(2, function_bit::kRetPos));
  const Bytes wire = encode_data_reply(2, Bytes{0x10, 0x27, 0x00, 0x00});
  const std::vector<Reply> replies = feed_bytewise(parser, wire);
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_EQ(decode_motion_reply(function_bit::kRetPos, replies[0].data)->position_counts, 10000);
  EXPECT_EQ(parser.counters().bytes, wire.size());
}

TEST(MotionMindReplyParser, AckIsOneByte) {
  ReplyParser parser;
  parser.expect(ack_reply());
  const auto reply = parser.feed(Bytes{0x00, 0x06});
  ASSERT_TRUE(reply);
  EXPECT_TRUE(reply->ack);
  EXPECT_EQ(parser.counters().discarded_bytes, 1u);
}

TEST(MotionMindReplyParser, GarbageBeforeAReplyIsSkipped) {
  ReplyParser parser;
  parser.expect(read_register_reply(3, Register::kStatus));
  // Noise, then a byte that looks like the address and starts a candidate whose checksum fails,
  // then the real reply: the parser drops the false start and finds the reply inside it.
  const Bytes wire{0x55, 0xAA, 0x03, 0x7F, 0x03, 0x01, 0x00, 0x04};
  const std::vector<Reply> replies = feed_bytewise(parser, wire);
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_EQ(register_value(mask_of(Register::kStatus), Register::kStatus, replies[0].data), 1);
  EXPECT_EQ(parser.counters().checksum_errors, 1u);
  EXPECT_EQ(parser.counters().discarded_bytes, 4u);
  EXPECT_EQ(parser.counters().replies, 1u);
}

TEST(MotionMindReplyParser, ABadChecksumIsCountedAndNeverPassedOn) {
  ReplyParser parser;
  parser.expect(motion_reply(1, function_bit::kRetPos));
  Bytes spoiled = encode_data_reply(1, Bytes{0xE8, 0x03, 0x00, 0x00});
  spoiled.back() ^= 0xFF;
  EXPECT_FALSE(parser.feed(spoiled));
  EXPECT_EQ(parser.counters().checksum_errors, 1u);
  EXPECT_EQ(parser.counters().replies, 0u);
  // Still awaiting: the good reply that follows (a retry) passes.
  EXPECT_TRUE(parser.awaiting());
  parser.cancel();
  parser.expect(motion_reply(1, function_bit::kRetPos));
  EXPECT_TRUE(parser.feed(encode_data_reply(1, Bytes{0xE8, 0x03, 0x00, 0x00})));
  const ReplyParser::Counters& counters = parser.counters();
  EXPECT_EQ(counters.bytes, 12u);
  EXPECT_EQ(counters.discarded_bytes, 6u);
  EXPECT_EQ(counters.abandoned, 1u);
}

TEST(MotionMindReplyParser, BytesNobodyWaitsForAreDiscarded) {
  ReplyParser parser;
  EXPECT_FALSE(parser.feed(Bytes{0x06, 0x01, 0x02}));
  EXPECT_EQ(parser.counters().discarded_bytes, 3u);
  // A reply takes only its own bytes; what follows in the same read is discarded.
  parser.expect(ack_reply());
  EXPECT_TRUE(parser.feed(Bytes{0x06, 0x06}));
  EXPECT_EQ(parser.counters().discarded_bytes, 4u);
}

TEST(MotionMindReplyParser, ANewExpectationAbandonsAPartialReply) {
  ReplyParser parser;
  parser.expect(motion_reply(1, function_bit::kRetPos));
  EXPECT_FALSE(parser.feed(Bytes{0x01, 0x02, 0x03}));
  EXPECT_EQ(parser.pending_bytes(), 3u);
  parser.expect(ack_reply());
  EXPECT_EQ(parser.pending_bytes(), 0u);
  EXPECT_EQ(parser.counters().abandoned, 1u);
  EXPECT_EQ(parser.counters().discarded_bytes, 3u);
}

TEST(MotionMindReplyParser, EveryByteIsAccountedFor) {
  // bytes = discarded + bytes of good replies + pending, whatever the stream.
  ReplyParser parser;
  std::uint64_t reply_bytes_total = 0;
  std::uint32_t state = 12345;
  for (int round = 0; round < 200; ++round) {
    const ExpectedReply expected = motion_reply(1, function_bit::kRetPos);
    parser.expect(expected);
    Bytes wire;
    for (int i = 0; i < round % 7; ++i) {
      state = state * 1103515245u + 12345u;
      wire.push_back(static_cast<std::uint8_t>(state >> 24));
    }
    Bytes good = encode_data_reply(1, Bytes{static_cast<std::uint8_t>(round), 0, 0, 0});
    if (round % 5 == 0) good.back() ^= 0x40;
    wire.insert(wire.end(), good.begin(), good.end());
    const std::vector<Reply> replies = feed_bytewise(parser, wire);
    // A spoiled reply never comes through; a good one does, after any garbage.
    ASSERT_EQ(replies.size(), round % 5 == 0 ? 0u : 1u) << "round " << round;
    for (const Reply& reply : replies) {
      EXPECT_EQ(reply.data[0], static_cast<std::uint8_t>(round));
      reply_bytes_total += reply.data.size() + 2;
    }
  }
  const ReplyParser::Counters& counters = parser.counters();
  EXPECT_EQ(counters.bytes, counters.discarded_bytes + reply_bytes_total + parser.pending_bytes());
  EXPECT_GE(counters.checksum_errors, 40u);
}

TEST(MotionMindUnits, WheelSpeedBecomesCountsPerPidPeriod) {
  // 38000 counts per wheel turn, 5 ms: 38000 * 0.005 / 2 pi = 30.24 per rad/s.
  EXPECT_NEAR(counts_per_period_per_radps(kR1WheelCountsPerRev), 30.2394, 1e-4);
  EXPECT_EQ(velocity_setpoint(1.0, kR1WheelCountsPerRev), 30);
  // 1 m/s on a 0.075 m wheel: 13.33 rad/s -> 403.2.
  EXPECT_EQ(velocity_setpoint(1.0 / 0.075, kR1WheelCountsPerRev), 403);
  EXPECT_EQ(velocity_setpoint(-1.0 / 0.075, kR1WheelCountsPerRev), -403);
  EXPECT_EQ(velocity_setpoint(std::numeric_limits<double>::quiet_NaN(), kR1WheelCountsPerRev), 0);
  EXPECT_EQ(velocity_setpoint(1e9, kR1WheelCountsPerRev), 32767);
  EXPECT_NEAR(setpoint_radps(403, kR1WheelCountsPerRev), 13.327, 1e-3);
  EXPECT_EQ(setpoint_radps(10, 0.0), 0.0);
}

TEST(MotionMindUnits, DitherAveragesTheExactSpeed) {
  SetpointDither dither;
  const double radps = 0.05;  // 1.512 units: plain rounding would give 2, 32 % fast
  long sum = 0;
  const int ticks = 1000;
  for (int i = 0; i < ticks; ++i) {
    const int setpoint = dither.next(radps, kR1WheelCountsPerRev);
    EXPECT_TRUE(setpoint == 1 || setpoint == 2);
    sum += setpoint;
  }
  EXPECT_NEAR(static_cast<double>(sum) / ticks, 1.512, 0.002);
  EXPECT_EQ(dither.next(0.0, kR1WheelCountsPerRev), 0);
  EXPECT_EQ(dither.next(0.0, kR1WheelCountsPerRev), 0);
}

TEST(MotionMindStatus, LimitSwitchBits) {
  EXPECT_TRUE(negative_limit(0x0001));
  EXPECT_FALSE(positive_limit(0x0001));
  EXPECT_TRUE(positive_limit(0x0002));
  EXPECT_FALSE(negative_limit(0xFFFE));
  const Status status = decode_status(status_bit::kNegativeLimit | status_bit::kInPosition |
                                      status_bit::kTemperatureFault);
  EXPECT_TRUE(status.negative_limit);
  EXPECT_FALSE(status.positive_limit);
  EXPECT_TRUE(status.in_position);
  EXPECT_TRUE(status.temperature_fault);
  EXPECT_FALSE(status.current_limit);
}

TEST(MotionMindPosition, UnwrapCarriesOnPastThe32BitLimits) {
  PositionUnwrap unwrap;
  constexpr std::int32_t kMax = std::numeric_limits<std::int32_t>::max();
  constexpr std::int32_t kMin = std::numeric_limits<std::int32_t>::min();
  EXPECT_EQ(unwrap.update(kMax - 10), std::int64_t{kMax} - 10);
  EXPECT_EQ(unwrap.update(kMin + 9), std::int64_t{kMax} + 10);  // +20 across the top
  EXPECT_EQ(unwrap.update(kMax - 5), std::int64_t{kMax} - 5);   // and back across it
  unwrap.reset();
  EXPECT_EQ(unwrap.update(-3), -3);
  EXPECT_EQ(unwrap.update(38000), 38000);
}

TEST(MotionMindTiming, RoundTripAtTheDefaultBaud) {
  // 19200 8N1: 0.52 ms a byte. MOVEAT_VELOCITY (5 bytes) answered by POSITION (6 bytes).
  EXPECT_NEAR(wire_time_s(5, kDefaultBaud), 0.0026042, 1e-6);
  EXPECT_NEAR(max_round_trip_s(5, 6, kDefaultBaud), 0.0026042 + 0.005 + 0.010 + 0.003125, 1e-6);
  EXPECT_NEAR(max_round_trip_s(8, 1, kDefaultBaud, true), 0.0041667 + 0.005 + 0.050 + 0.00052,
              1e-6);
}

TEST(MotionMindSetup, TiltSetupWritesItsPidAndAsksForPositions) {
  const std::vector<Exchange> exchanges = setup_exchanges(3, r1_tilt_setup());
  ASSERT_EQ(exchanges.size(), 4u);
  for (const Exchange& exchange : exchanges) EXPECT_TRUE(exchange.reply.ack);
  EXPECT_EQ(exchanges[0].command, write_register(3, Register::kPTerm, 6000));
  EXPECT_EQ(exchanges[1].command, write_register(3, Register::kITerm, 35));
  EXPECT_EQ(exchanges[2].command, write_register(3, Register::kDTerm, 2));
  EXPECT_EQ(exchanges[3].command, write_register(3, Register::kFunction, function_bit::kRetPos));
  EXPECT_EQ(r1_wheel_setup().d_term, 0);
}

TEST(MotionMindRegisters, TableMatchesTheDataSheet) {
  EXPECT_EQ(register_info(Register::kPosition).size_bytes, 4);
  EXPECT_TRUE(register_info(Register::kPosition).is_signed);
  EXPECT_EQ(register_info(Register::kVelocityFf).size_bytes, 1);
  EXPECT_EQ(register_info(Register::kPTerm).default_value, 6000);
  EXPECT_EQ(register_info(Register::kITerm).default_value, 35);
  EXPECT_FALSE(register_info(Register::kStatus).writable);
  EXPECT_EQ(register_info(Register::kThermistor).name, "THERMISTOR");
  EXPECT_FALSE(register_from_index(32));
  EXPECT_NEAR(thermistor_celsius(952), 25.08, 0.01);
  EXPECT_NEAR(amps_register_amperes(512), 10.24, 1e-9);
}

}  // namespace
}  // namespace mobot::protocol::motion_mind
