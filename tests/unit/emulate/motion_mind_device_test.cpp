#include "tools/emulate/devices/motion_mind_device.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <vector>

#include "drivers/protocol/motion_mind.h"
#include "tests/unit/emulate/line_harness.h"

namespace mobot::emulate {
namespace {

namespace mm = protocol::motion_mind;

constexpr double kStep_s = 0.001;
constexpr double kTimeout_s = 0.05;

// The host side of the line, as a driver would run it: arm the parser, write the command, read
// what comes back every millisecond until the reply is whole or the time-out passes.
class Host {
 public:
  explicit Host(MotionMindBus& bus, MotionMindBaseCoupling* coupling = nullptr)
      : bus_(bus), coupling_(coupling) {}

  std::optional<mm::Reply> exchange(const mm::Packet& command, const mm::ExpectedReply& expected) {
    parser_.expect(expected);
    bus_.receive(command, now_s_);
    sent_s_ = now_s_;
    const double deadline_s = now_s_ + kTimeout_s;
    while (now_s_ < deadline_s) {
      std::optional<mm::Reply> reply = tick();
      if (reply) {
        round_trip_s_ = now_s_ - sent_s_;
        return reply;
      }
    }
    parser_.cancel();
    return std::nullopt;
  }

  void run_for(double duration_s) {
    const double end_s = now_s_ + duration_s;
    while (now_s_ < end_s - 1e-12) tick();
  }

  // Sets the speed and returns POSITION from the answer (FUNCTION.RETPOS set).
  std::optional<std::int32_t> drive(std::uint8_t address, int counts_per_period) {
    const auto reply = exchange(mm::move_at_velocity(address, counts_per_period),
                                mm::motion_reply(address, mm::function_bit::kRetPos));
    if (!reply) return std::nullopt;
    return mm::decode_motion_reply(mm::function_bit::kRetPos, reply->data)->position_counts;
  }

  std::optional<std::int64_t> read(std::uint8_t address, mm::Register reg) {
    const auto reply =
        exchange(mm::read_register(address, reg), mm::read_register_reply(address, reg));
    if (!reply) return std::nullopt;
    return mm::register_value(mm::mask_of(reg), reg, reply->data);
  }

  void set_up(std::uint8_t address, const mm::BoardSetup& setup) {
    for (const mm::Exchange& step : mm::setup_exchanges(address, setup)) {
      const auto reply = exchange(step.command, step.reply);
      ASSERT_TRUE(reply);
      ASSERT_TRUE(reply->ack);
    }
  }

  double now_s() const { return now_s_; }
  double round_trip_s() const { return round_trip_s_; }
  const mm::ReplyParser& parser() const { return parser_; }

 private:
  std::optional<mm::Reply> tick() {
    now_s_ += kStep_s;
    std::optional<mm::Reply> reply = parser_.feed(bus_.transmit(now_s_));
    if (coupling_ != nullptr) coupling_->update();
    return reply;
  }

  MotionMindBus& bus_;
  MotionMindBaseCoupling* coupling_;
  mm::ReplyParser parser_;
  double now_s_ = 0.0;
  double sent_s_ = 0.0;
  double round_trip_s_ = 0.0;
};

MotionMindBoardOptions wheel(std::uint8_t address) {
  MotionMindBoardOptions options;
  options.address = address;
  return options;
}

MotionMindBusOptions two_wheels() {
  MotionMindBusOptions options;
  options.boards = {wheel(1), wheel(2)};
  return options;
}

TEST(MotionMindDevice, ASpeedSetPointAdvancesPositionAtItsRate) {
  MotionMindBus bus(two_wheels());
  Host host(bus);
  host.set_up(1, mm::r1_wheel_setup());
  const double radps = 2.0;
  const int setpoint = mm::velocity_setpoint(radps, mm::kR1WheelCountsPerRev);  // 60
  ASSERT_EQ(setpoint, 60);
  ASSERT_TRUE(host.drive(1, setpoint));
  host.run_for(0.5);  // ten time constants: at speed
  EXPECT_NEAR(*bus.shaft_speed_radps(1), radps, 0.01 * radps);

  const std::optional<std::int32_t> first = host.drive(1, setpoint);
  const double first_s = host.now_s();
  host.run_for(2.0);
  const std::optional<std::int32_t> second = host.drive(1, setpoint);
  const double elapsed_s = host.now_s() - first_s;
  ASSERT_TRUE(first && second);
  // 60 counts per 5 ms = 12000 counts/s.
  EXPECT_NEAR((*second - *first) / elapsed_s, 12000.0, 0.01 * 12000.0);
  // VELOCITY averages the last 64 periods in the same unit.
  EXPECT_NEAR(static_cast<double>(*host.read(1, mm::Register::kVelocity)), 60.0, 1.0);
  // The other board was never told to move.
  EXPECT_EQ(*host.read(2, mm::Register::kPosition), 0);
}

TEST(MotionMindDevice, AnExchangeTakesTheGapTheDelayAndTheWire) {
  MotionMindBus bus(two_wheels());
  Host host(bus);
  host.set_up(1, mm::r1_wheel_setup());
  ASSERT_TRUE(host.drive(1, 0));
  // 5 ms of quiet ends the command, 2 ms to answer, 6 bytes at 19200 baud (3.1 ms).
  EXPECT_NEAR(host.round_trip_s(), 0.005 + 0.002 + mm::wire_time_s(6, mm::kDefaultBaud),
              kStep_s + 1e-9);
  EXPECT_LE(host.round_trip_s(), mm::max_round_trip_s(0, 6, mm::kDefaultBaud));
}

TEST(MotionMindDevice, OnlyTheAddressedBoardAnswers) {
  MotionMindBus bus(two_wheels());
  Host host(bus);
  const auto reply = host.exchange(mm::read_register(2, mm::Register::kMode),
                                   mm::read_register_reply(2, mm::Register::kMode));
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->address, 2);
  EXPECT_EQ(mm::register_value(mm::mask_of(mm::Register::kMode), mm::Register::kMode, reply->data),
            4);
  EXPECT_FALSE(host.read(3, mm::Register::kPosition));
  EXPECT_EQ(bus.commands(), 2u);

  // A broadcast moves every board and none answers.
  EXPECT_FALSE(host.exchange(mm::move_at_velocity(mm::kBroadcastAddress, 20), mm::ack_reply()));
  host.run_for(0.5);
  EXPECT_GT(*bus.position_register(1), 1000);
  EXPECT_GT(*bus.position_register(2), 1000);
}

TEST(MotionMindDevice, TwoCommandsWithoutAPauseAreOneBadCommand) {
  MotionMindBus bus(two_wheels());
  Host host(bus);
  mm::Packet both = mm::read_register(1, mm::Register::kPosition);
  const mm::Packet second = mm::read_register(2, mm::Register::kPosition);
  both.insert(both.end(), second.begin(), second.end());
  EXPECT_FALSE(host.exchange(both, mm::read_register_reply(1, mm::Register::kPosition)));
  EXPECT_EQ(bus.rejected_commands(), 1u);
  // Split into two writes 1 ms apart, still within the 5 ms: the same.
  bus.receive(mm::read_register(1, mm::Register::kPosition), host.now_s());
  host.run_for(0.001);
  EXPECT_FALSE(host.exchange(second, mm::read_register_reply(2, mm::Register::kPosition)));
  EXPECT_EQ(bus.rejected_commands(), 2u);
  EXPECT_TRUE(host.read(2, mm::Register::kPosition));
}

TEST(MotionMindDevice, SpoiledChecksumsAreDroppedByTheHost) {
  MotionMindBus bus(two_wheels());
  Host host(bus);
  bus.set_bad_checksums(true);
  EXPECT_FALSE(host.read(1, mm::Register::kPosition));
  EXPECT_EQ(host.parser().counters().checksum_errors, 1u);
  EXPECT_EQ(host.parser().counters().replies, 0u);
  // ACK carries no checksum and still passes.
  const auto ack = host.exchange(mm::write_register(1, mm::Register::kDTerm, 1), mm::ack_reply());
  ASSERT_TRUE(ack);
  EXPECT_TRUE(ack->ack);
  bus.set_bad_checksums(false);
  EXPECT_EQ(host.read(1, mm::Register::kDTerm), 1);
}

TEST(MotionMindDevice, TheTiltSwitchClosesAtTheLowerEndAndStopsTheAxis) {
  MotionMindBusOptions options;
  MotionMindBoardOptions tilt;
  tilt.address = 3;
  tilt.counts_per_rev = 200.0 * 360.0;
  tilt.tilt = MotionMindTiltOptions{200.0, -5.0, 10.0};
  options.boards = {tilt};
  MotionMindBus bus(options);
  Host host(bus);
  host.set_up(3, mm::r1_tilt_setup());
  EXPECT_EQ(host.read(3, mm::Register::kDTerm), 2);

  // Down at 5 deg/s (1000 counts/s = 5 counts per period) until the switch shows.
  const mm::RegisterMask mask =
      mm::mask_of(mm::Register::kPosition) | mm::mask_of(mm::Register::kStatus);
  ASSERT_TRUE(host.drive(3, -5));
  bool closed = false;
  for (int poll = 0; poll < 400 && !closed; ++poll) {
    host.run_for(0.02);
    const auto reply = host.exchange(mm::read_registers(3, mask), mm::read_reply(3, mask));
    ASSERT_TRUE(reply);
    closed = mm::negative_limit(
        static_cast<std::uint16_t>(*mm::register_value(mask, mm::Register::kStatus, reply->data)));
  }
  ASSERT_TRUE(closed);
  // Closed at -5 deg, shown after the 50 ms debounce: at most 0.25 deg past it plus one poll.
  EXPECT_LE(*bus.tilt_pitch_deg(3), -5.0);
  EXPECT_GE(*bus.tilt_pitch_deg(3), -5.0 - 0.25 - 0.15);

  // The board will not drive further down, whatever it is told.
  const double stopped_deg = *bus.tilt_pitch_deg(3);
  host.drive(3, -5);
  host.run_for(1.0);
  EXPECT_NEAR(*bus.tilt_pitch_deg(3), stopped_deg, 0.01);

  // Up again: the switch opens.
  host.drive(3, 5);
  host.run_for(0.5);
  EXPECT_GT(*bus.tilt_pitch_deg(3), -5.0);
  EXPECT_FALSE(
      mm::negative_limit(static_cast<std::uint16_t>(*host.read(3, mm::Register::kStatus))));
}

TEST(MotionMindDevice, PositionWrapsAt32BitsAndTheHostUnwrapsIt) {
  MotionMindBusOptions options = two_wheels();
  options.boards[0].initial_position_counts = std::numeric_limits<std::int32_t>::max() - 3000;
  MotionMindBus bus(options);
  Host host(bus);
  host.set_up(1, mm::r1_wheel_setup());
  mm::PositionUnwrap unwrap;
  const std::int64_t start = unwrap.update(*host.drive(1, 100));
  bool wrapped = false;
  std::int64_t last = start;
  for (int tick = 0; tick < 50; ++tick) {
    host.run_for(0.02);
    const std::int32_t raw = *host.drive(1, 100);
    wrapped = wrapped || raw < 0;
    const std::int64_t total = unwrap.update(raw);
    EXPECT_GT(total, last);
    last = total;
  }
  EXPECT_TRUE(wrapped);
  EXPECT_GT(last, std::int64_t{std::numeric_limits<std::int32_t>::max()} + 10000);
}

TEST(MotionMindDevice, WritesReadsRestoreAndReset) {
  MotionMindBus bus(two_wheels());
  Host host(bus);
  ASSERT_TRUE(
      host.exchange(mm::write_register(2, mm::Register::kPosition, -10000), mm::ack_reply()));
  EXPECT_EQ(host.read(2, mm::Register::kPosition), -10000);
  // A read-only register keeps its value.
  ASSERT_TRUE(host.exchange(mm::write_register(2, mm::Register::kMode, 1), mm::ack_reply()));
  EXPECT_EQ(host.read(2, mm::Register::kMode), 4);
  // RESET reloads the stored registers and zeroes POSITION.
  ASSERT_TRUE(host.exchange(mm::write_register(2, mm::Register::kPTerm, 100), mm::ack_reply()));
  ASSERT_TRUE(host.exchange(mm::reset(2), mm::ack_reply()));
  EXPECT_EQ(host.read(2, mm::Register::kPTerm), 6000);
  EXPECT_EQ(host.read(2, mm::Register::kPosition), 0);
  // RESTORE brings the factory address back: board 2 answers at 1 alongside board 1.
  ASSERT_TRUE(host.exchange(mm::restore_defaults(2), mm::ack_reply()));
  EXPECT_FALSE(host.read(2, mm::Register::kPosition));
}

TEST(MotionMindDevice, TheSameSeedGivesTheSameBytes) {
  auto run = [] {
    MotionMindBus bus(two_wheels());
    Host host(bus);
    host.set_up(1, mm::r1_wheel_setup());
    std::vector<std::int32_t> positions;
    for (int tick = 0; tick < 20; ++tick) {
      positions.push_back(*host.drive(1, 77));
      host.run_for(0.02);
    }
    return positions;
  };
  EXPECT_EQ(run(), run());
}

TEST(MotionMindDevice, BadOptionsAreRefused) {
  MotionMindBusOptions duplicate = two_wheels();
  duplicate.boards[1].address = 1;
  EXPECT_THROW(MotionMindBus{duplicate}, std::invalid_argument);
  MotionMindBusOptions no_scale = two_wheels();
  no_scale.boards[0].counts_per_rev = 0.0;
  EXPECT_THROW(MotionMindBus{no_scale}, std::invalid_argument);
  MotionMindBus bus(two_wheels());
  testing::EmptyWorld world;
  EXPECT_THROW(MotionMindBaseCoupling(bus, 1, 5, world), std::invalid_argument);
}

TEST(MotionMindDevice, HostileTimesDoNotMoveTheClockBack) {
  MotionMindBus bus(two_wheels());
  bus.receive(mm::read_register(1, mm::Register::kTime), 1.0);
  EXPECT_TRUE(bus.transmit(std::numeric_limits<double>::quiet_NaN()).empty());
  EXPECT_TRUE(bus.transmit(0.5).empty());
  const std::vector<std::uint8_t> reply = bus.transmit(1.1);
  ASSERT_EQ(reply.size(), 6u);
  // TIME counts the 5 ms periods up to the end of the command (1.005 s).
  EXPECT_EQ(mm::register_value(mm::mask_of(mm::Register::kTime), mm::Register::kTime,
                               std::span<const std::uint8_t>(reply).subspan(1, 4)),
            201);
  // A gap of hours is jumped.
  bus.receive(mm::move_at_velocity(1, 10), 1.2);
  EXPECT_FALSE(bus.transmit(1.3).empty());
  bus.transmit(36000.0);
  // 10 counts per period from 1.205 s on, less the lag (10 x 0.05 / 0.005 = 100 counts).
  EXPECT_NEAR(*bus.position_register(1), 10 * 200 * (36000.0 - 1.205), 200.0);
}

TEST(MotionMindBaseCouplingTest, EqualSpeedsDriveStraight) {
  MotionMindBus bus(two_wheels());
  testing::EmptyWorld world;
  world.set_base_pose({1.0, 2.0, std::numbers::pi / 2});
  MotionMindBaseCoupling coupling(bus, 1, 2, world);
  Host host(bus, &coupling);
  host.set_up(1, mm::r1_wheel_setup());
  host.set_up(2, mm::r1_wheel_setup());
  host.drive(1, 100);
  host.drive(2, 100);
  host.run_for(2.0);
  host.drive(1, 0);
  host.drive(2, 0);
  host.run_for(0.5);
  const double left_m = *bus.shaft_angle_rad(1) * 0.075;
  const double right_m = *bus.shaft_angle_rad(2) * 0.075;
  // 100 counts per 5 ms for ~2 s: 40000 counts, 1.05 turns, 0.496 m; the wheels within noise of
  // each other.
  EXPECT_NEAR(left_m, 0.496, 0.03);
  EXPECT_NEAR(right_m, left_m, 0.005);
  const geometry::Pose2D pose = world.base_pose();
  EXPECT_NEAR(pose.x, 1.0, 0.01);
  EXPECT_NEAR(pose.y, 2.0 + 0.5 * (left_m + right_m), 1e-4);
  EXPECT_NEAR(pose.theta, std::numbers::pi / 2 + (right_m - left_m) / 0.60, 1e-6);
}

TEST(MotionMindBaseCouplingTest, OppositeSpeedsTurnOnTheSpot) {
  MotionMindBus bus(two_wheels());
  testing::EmptyWorld world;
  MotionMindBaseCoupling coupling(bus, 1, 2, world);
  Host host(bus, &coupling);
  host.set_up(1, mm::r1_wheel_setup());
  host.set_up(2, mm::r1_wheel_setup());
  host.drive(1, -30);
  host.drive(2, 30);
  host.run_for(1.0);
  host.drive(1, 0);
  host.drive(2, 0);
  host.run_for(0.5);
  const double left_m = *bus.shaft_angle_rad(1) * 0.075;
  const double right_m = *bus.shaft_angle_rad(2) * 0.075;
  ASSERT_LT(left_m, -0.05);
  ASSERT_GT(right_m, 0.05);
  const geometry::Pose2D pose = world.base_pose();
  EXPECT_NEAR(pose.theta, geometry::wrap_angle((right_m - left_m) / 0.60), 1e-6);
  EXPECT_GT(pose.theta, 0.2);  // counter-clockwise
  EXPECT_NEAR(pose.x, 0.0, 0.005);
  EXPECT_NEAR(pose.y, 0.0, 0.005);
}

}  // namespace
}  // namespace mobot::emulate
