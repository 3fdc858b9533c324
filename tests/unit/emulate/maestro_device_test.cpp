#include "tools/emulate/devices/maestro_device.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <vector>

#include "drivers/protocol/pololu_maestro.h"
#include "tests/unit/emulate/line_harness.h"

namespace mobot::emulate {
namespace {

namespace mx = protocol::maestro;

constexpr double kStep_s = 0.001;
constexpr double kRadPerDeg = std::numbers::pi / 180.0;

// The host's side without a pty: bytes in at the model's time, answers collected every
// millisecond.
class Host {
 public:
  explicit Host(MaestroDevice& maestro) : maestro_(maestro) {}

  void send(const mx::Packet& bytes) { maestro_.receive(bytes, now_s_); }
  // Sends `bytes` and returns what comes back within `window_s`.
  std::vector<std::uint8_t> ask(const mx::Packet& bytes, double window_s = 0.005) {
    send(bytes);
    std::vector<std::uint8_t> answer;
    const double end_s = now_s_ + window_s;
    while (now_s_ < end_s - 1e-12) {
      now_s_ += kStep_s;
      const std::vector<std::uint8_t> out = maestro_.transmit(now_s_);
      answer.insert(answer.end(), out.begin(), out.end());
    }
    return answer;
  }
  std::optional<std::uint16_t> position(int channel) {
    const std::vector<std::uint8_t> answer =
        ask(mx::get_position(static_cast<std::uint8_t>(channel)));
    if (answer.size() != 2) return std::nullopt;
    return static_cast<std::uint16_t>(answer[0] | (answer[1] << 8));
  }
  std::optional<std::uint16_t> errors() {
    const std::vector<std::uint8_t> answer = ask(mx::get_errors());
    if (answer.size() != 2) return std::nullopt;
    return static_cast<std::uint16_t>(answer[0] | (answer[1] << 8));
  }
  // How long after `bytes` the `count`th byte of the answer comes, to the millisecond.
  double answer_delay_s(const mx::Packet& bytes, std::size_t count) {
    send(bytes);
    const double sent_s = now_s_;
    std::size_t received = 0;
    while (received < count && now_s_ < sent_s + 0.1) {
      now_s_ += kStep_s;
      received += maestro_.transmit(now_s_).size();
    }
    return now_s_ - sent_s;
  }
  void run_for(double duration_s) {
    const double end_s = now_s_ + duration_s;
    while (now_s_ < end_s - 1e-12) {
      now_s_ += kStep_s;
      maestro_.transmit(now_s_);
    }
  }
  double now_s() const { return now_s_; }

 private:
  MaestroDevice& maestro_;
  double now_s_ = 0.0;
};

class MaestroDeviceTest : public ::testing::Test {
 protected:
  MaestroDevice& make(MaestroDeviceOptions options = {}) {
    maestro_ = std::make_unique<MaestroDevice>(options, world_);
    host_ = std::make_unique<Host>(*maestro_);
    return *maestro_;
  }

  // A 4 x 4 m room around the origin, the base at its centre facing +x.
  testing::BoxWorld world_{-2.0, 2.0, -2.0, 2.0};
  std::unique_ptr<MaestroDevice> maestro_;
  std::unique_ptr<Host> host_;
};

TEST_F(MaestroDeviceTest, AnswersPositionsLittleEndianAndTheFirstTargetJumps) {
  make();
  EXPECT_EQ(host_->position(0), 0);  // off at power-up
  host_->send(mx::set_target(0, 6000));
  // Off, the servo cannot be slewed from where it is: its first pulse is the target.
  const std::vector<std::uint8_t> answer = host_->ask(mx::get_position(0));
  EXPECT_EQ(answer, (std::vector<std::uint8_t>{0x70, 0x17}));
  EXPECT_EQ(maestro_->pan_rad(), 0.0);
  EXPECT_FALSE(maestro_->tilt_rad());
  EXPECT_EQ(maestro_->commands(), 3U);
}

TEST_F(MaestroDeviceTest, SlewsAtTheSpeedLimit) {
  make();
  host_->send(mx::set_target(0, 6000));
  host_->run_for(0.02);
  // Speed 40: 10 us per 10 ms, 1000 us/s: 1500 -> 2000 us takes 0.5 s.
  host_->send(mx::set_speed(0, 40));
  host_->send(mx::set_target(0, 8000));
  host_->run_for(0.25);
  EXPECT_NEAR(*host_->position(0), 7000, 45);
  std::vector<std::uint8_t> moving = host_->ask(mx::get_moving_state());
  EXPECT_EQ(moving, (std::vector<std::uint8_t>{1}));
  host_->run_for(0.3);
  EXPECT_EQ(host_->position(0), 8000);
  moving = host_->ask(mx::get_moving_state());
  EXPECT_EQ(moving, (std::vector<std::uint8_t>{0}));
}

TEST_F(MaestroDeviceTest, AccelerationRampsUpAndBrakesOntoTheTarget) {
  make();
  host_->send(mx::set_target(0, 4000));
  host_->run_for(0.02);
  host_->send(mx::set_speed(0, 100));
  host_->send(mx::set_acceleration(0, 10));
  host_->send(mx::set_target(0, 8000));
  // The speed grows by 10/8 per 10 ms (it would take 0.8 s to reach 100): after 20 ticks the
  // servo has moved 1.25 x 20 x 21 / 2 = 262 quarter-us, where full speed would have gone 2000.
  host_->run_for(0.2);
  const std::uint16_t early = *host_->position(0);
  EXPECT_GT(early, 4200);
  EXPECT_LT(early, 4700);
  std::uint16_t last = early;
  bool monotonic = true;
  for (int i = 0; i < 300; ++i) {
    host_->run_for(0.01);
    const std::uint16_t now = *host_->position(0);
    monotonic = monotonic && now >= last && now <= 8000;
    last = now;
  }
  EXPECT_TRUE(monotonic);
  EXPECT_EQ(last, 8000);
}

TEST_F(MaestroDeviceTest, TargetsAreClampedToTheChannelsMinAndMax) {
  MaestroDeviceOptions options;
  options.min_pulse_us = 900.0;
  options.max_pulse_us = 2100.0;
  make(options);
  host_->send(mx::set_target(1, 12000));
  EXPECT_EQ(host_->position(1), 8400);
  host_->send(mx::set_target(1, 1000));
  host_->run_for(0.02);
  EXPECT_EQ(host_->position(1), 3600);
  EXPECT_EQ(maestro_->target_qus(1), 3600);
  // Target 0 switches the servo off.
  host_->send(mx::set_target(1, 0));
  EXPECT_EQ(host_->position(1), 0);
}

TEST_F(MaestroDeviceTest, TheRangerReadsTheWallAlongThePan) {
  MaestroDeviceOptions options;
  make(options);
  const vision::PanTiltHead head(options.head);
  host_->send(mx::set_target(0, 6000));
  host_->send(mx::set_target(1, 6000));
  host_->run_for(0.1);
  // Straight ahead: the wall at x = 2 m from the lens.
  const double ahead_m = 2.0 - head.lens_in_base({}).x_m;
  ASSERT_TRUE(maestro_->ranger_range_m());
  EXPECT_NEAR(*maestro_->ranger_range_m(), ahead_m, 1e-9);
  const std::uint16_t value = *host_->position(options.range_channel);
  EXPECT_EQ(value, maestro_->ranger_value());
  EXPECT_NEAR(*mx::range_from_analog(value, mx::RangerScale{}), ahead_m, 0.03);
  // Panned 90 deg to the left: the wall at y = 2 m.
  host_->send(mx::set_target(0, mx::target_for_angle(options.pan, 90.0 * kRadPerDeg)));
  host_->run_for(0.1);
  const double left_m = 2.0 - head.lens_in_base({90.0 * kRadPerDeg, 0.0}).y_m;
  EXPECT_NEAR(*mx::range_from_analog(*host_->position(options.range_channel), mx::RangerScale{}),
              left_m, 0.03);
}

TEST_F(MaestroDeviceTest, NoEchoReadsTheLvEzsMaximum) {
  testing::EmptyWorld empty;
  MaestroDevice maestro({}, empty);
  Host host(maestro);
  host.run_for(0.1);
  EXPECT_FALSE(maestro.ranger_range_m());
  // 254 inches at 5 V: 2.48 V, 508 of 1023.
  EXPECT_EQ(host.position(2), 508);
  EXPECT_FALSE(mx::range_from_analog(508, mx::RangerScale{}));
}

TEST_F(MaestroDeviceTest, AProtocolErrorIsRecordedAndSendsTheServosHome) {
  make();
  host_->send(mx::set_target(0, 6000));
  host_->run_for(0.02);
  EXPECT_EQ(host_->position(0), 6000);
  host_->send(mx::Packet{0x80});  // no such command
  EXPECT_EQ(maestro_->errors(), mx::error_bit::kSerialProtocol);
  EXPECT_EQ(host_->position(0), 0);  // home is "off"
  EXPECT_EQ(host_->errors(), mx::error_bit::kSerialProtocol);
  EXPECT_EQ(host_->errors(), 0);  // read, so cleared
  // A channel the Micro Maestro does not have.
  EXPECT_FALSE(host_->position(9));
  EXPECT_EQ(host_->errors(), mx::error_bit::kSerialProtocol);
}

TEST_F(MaestroDeviceTest, AHomePositionIsSlewedTo) {
  MaestroDeviceOptions options;
  options.home_qus = 6000;
  make(options);
  host_->send(mx::set_target(0, 8000));
  host_->send(mx::set_speed(0, 40));
  host_->run_for(0.02);
  maestro_->raise_errors(mx::error_bit::kSerialTimeout);
  host_->run_for(0.25);
  EXPECT_NEAR(*host_->position(0), 7000, 45);
  EXPECT_EQ(maestro_->target_qus(0), 6000);
}

TEST_F(MaestroDeviceTest, RepeatedErrorsKeepComing) {
  make();
  maestro_->keep_raising_errors(mx::error_bit::kSerialTimeout);
  host_->run_for(0.05);
  EXPECT_EQ(host_->errors(), mx::error_bit::kSerialTimeout);
  host_->run_for(0.05);
  EXPECT_EQ(host_->errors(), mx::error_bit::kSerialTimeout);
  maestro_->keep_raising_errors(0);
  host_->errors();
  EXPECT_EQ(host_->errors(), 0);
}

TEST_F(MaestroDeviceTest, WithCrcOnlyCommandsWithTheirCrcAreTaken) {
  MaestroDeviceOptions options;
  options.crc = true;
  make(options);
  EXPECT_EQ(host_->ask(mx::with_crc(mx::get_position(0))).size(), 2U);
  // Without its CRC the query is not whole; the next command byte makes it a protocol error.
  EXPECT_TRUE(host_->ask(mx::get_position(0)).empty());
  mx::Packet wrong = mx::with_crc(mx::get_errors());
  wrong.back() ^= 0x01;
  EXPECT_TRUE(host_->ask(wrong).empty());
  EXPECT_EQ(maestro_->errors(), mx::error_bit::kSerialProtocol | mx::error_bit::kSerialCrc);
}

TEST_F(MaestroDeviceTest, BadChecksumsGarbleTheAnswers) {
  make();
  host_->send(mx::set_target(0, 6000));
  maestro_->set_bad_checksums(true);
  const std::vector<std::uint8_t> answer = host_->ask(mx::get_position(0));
  ASSERT_EQ(answer.size(), 2U);
  EXPECT_FALSE(
      mx::plausible_servo_position(static_cast<std::uint16_t>(answer[0] | (answer[1] << 8))));
  maestro_->set_bad_checksums(false);
  EXPECT_EQ(host_->position(0), 6000);
}

TEST_F(MaestroDeviceTest, SetMultipleTargetsOnlyOnAMiniMaestro) {
  make();
  const std::vector<std::uint16_t> targets{5000, 7000};
  host_->send(mx::set_multiple_targets(0, targets));
  EXPECT_EQ(host_->position(0), 0);
  EXPECT_EQ(host_->errors(), mx::error_bit::kSerialProtocol);
  MaestroDeviceOptions mini;
  mini.channels = 12;
  make(mini);
  host_->send(mx::set_multiple_targets(0, targets));
  EXPECT_EQ(host_->position(0), 5000);
  EXPECT_EQ(host_->position(1), 7000);
}

TEST_F(MaestroDeviceTest, AnswersLeaveAtTheBaudRate) {
  MaestroDeviceOptions options;
  options.baud = 9600;
  make(options);
  host_->send(mx::set_target(0, 6000));
  // Two bytes at 9600 baud: 2.1 ms after the 0.5 ms response delay.
  EXPECT_NEAR(host_->answer_delay_s(mx::get_position(0), 2), 0.003, 0.0011);
  options.baud = 115200;
  make(options);
  EXPECT_NEAR(host_->answer_delay_s(mx::get_position(0), 2), 0.001, 0.0011);
}

TEST(MaestroDeviceOptions, BadOptionsAreRefused) {
  testing::EmptyWorld world;
  const auto refused = [&](const std::function<void(MaestroDeviceOptions&)>& spoil) {
    MaestroDeviceOptions options;
    spoil(options);
    try {
      MaestroDevice maestro(options, world);
    } catch (const std::invalid_argument&) {
      return true;
    }
    return false;
  };
  EXPECT_FALSE(refused([](MaestroDeviceOptions&) {}));
  EXPECT_TRUE(refused([](MaestroDeviceOptions& o) { o.pan_channel = 6; }));
  EXPECT_TRUE(refused([](MaestroDeviceOptions& o) { o.tilt_channel = 0; }));
  EXPECT_TRUE(refused([](MaestroDeviceOptions& o) { o.range_channel = 1; }));
  EXPECT_TRUE(refused([](MaestroDeviceOptions& o) {
    o.channels = 24;
    o.range_channel = 12;  // a digital input
  }));
  EXPECT_TRUE(refused([](MaestroDeviceOptions& o) { o.pan.sign = 0; }));
  EXPECT_TRUE(refused([](MaestroDeviceOptions& o) { o.max_pulse_us = 400.0; }));
  EXPECT_TRUE(refused([](MaestroDeviceOptions& o) { o.range_period_s = 0.0; }));
}

}  // namespace
}  // namespace mobot::emulate
