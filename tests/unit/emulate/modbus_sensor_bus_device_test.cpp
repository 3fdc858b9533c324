#include "tools/emulate/devices/modbus_sensor_bus_device.h"
#include "tests/unit/emulate/line_harness.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace mobot::emulate {
namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr double kPi = std::numbers::pi;
// At 115200 baud: 10 bits a byte, and t3.5 fixed at 1.75 ms.
constexpr double kByte_s = 10.0 / 115200.0;
constexpr double kSilence_s = 0.00175;
constexpr double kLater_s = 1.0;  // long after any reply has gone out

ModbusSensorBusOptions quiet_options() {
  ModbusSensorBusOptions options;
  options.compass_noise_rad = 0.0;
  options.sonar_noise_fraction = 0.0;
  return options;
}

class ModbusSensorBusDeviceTest : public ::testing::Test {
 protected:
  // Sends `request` at t = 0 and collects everything the device says by kLater_s.
  Bytes exchange(const Bytes& request) {
    now_s_ += kLater_s;
    device_.receive(request, now_s_);
    now_s_ += kLater_s;
    return device_.transmit(now_s_);
  }

  // The room reaches 1 m in front of the left-side sonars (at y = 0.30) and 5 m elsewhere.
  testing::BoxWorld world_{-5.0, 5.0, -5.0, 1.30};
  ModbusSensorBusDevice device_{world_, quiet_options(), 7};
  double now_s_ = 0.0;
};

TEST(ModbusCrc16, MatchesTheCatalogueCheckValue) {
  const std::string_view digits = "123456789";
  const Bytes bytes(digits.begin(), digits.end());
  EXPECT_EQ(modbus_crc16(bytes), 0x4B37);
}

TEST_F(ModbusSensorBusDeviceTest, AnswersTheCompassHeadingByteForByte) {
  // Read input register 0 of slave 1; its CRC is the spec's usual example.
  EXPECT_EQ(exchange({0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCA}),
            (Bytes{0x01, 0x04, 0x02, 0x00, 0x00, 0xB9, 0x30}));
  // Facing +y in the map: a quarter turn counter-clockwise, 270.0 degrees on the compass.
  world_.set_base_pose({0.0, 0.0, kPi / 2.0});
  EXPECT_EQ(exchange({0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCA}),
            (Bytes{0x01, 0x04, 0x02, 0x0A, 0x8C, 0xBE, 0x35}));
  // Function 3 reads the same table.
  EXPECT_EQ(exchange({0x01, 0x03, 0x00, 0x00, 0x00, 0x01, 0x84, 0x0A}),
            (Bytes{0x01, 0x03, 0x02, 0x0A, 0x8C, 0xBF, 0x41}));
}

TEST_F(ModbusSensorBusDeviceTest, TheHeadingOffsetIsWhereTheCompassReadsZero) {
  ModbusSensorBusOptions options = quiet_options();
  options.heading_offset_rad = kPi / 2.0;
  ModbusSensorBusDevice device(world_, options, 1);
  world_.set_base_pose({0.0, 0.0, kPi / 2.0});
  device.receive(Bytes{0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCA}, 0.0);
  EXPECT_EQ(device.transmit(kLater_s), (Bytes{0x01, 0x04, 0x02, 0x00, 0x00, 0xB9, 0x30}));
  // A little counter-clockwise of that reads a little below 360 degrees: 350.0.
  world_.set_base_pose({0.0, 0.0, kPi / 2.0 + 10.0 * kPi / 180.0});
  device.receive(Bytes{0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCA}, 2.0);
  const Bytes reply = device.transmit(3.0);
  ASSERT_EQ(reply.size(), 7u);
  EXPECT_EQ((reply[3] << 8) | reply[4], 3500);
}

TEST_F(ModbusSensorBusDeviceTest, ASonarReadsTheNearestEchoInMillimetres) {
  // Sonar 5 (slave 6) sits at (0.15, 0.30) looking along +y: the wall is 1.000 m ahead on its
  // axis, further along every other ray of the cone.
  EXPECT_EQ(exchange({0x06, 0x04, 0x00, 0x00, 0x00, 0x01, 0x30, 0x7D}),
            (Bytes{0x06, 0x04, 0x02, 0x03, 0xE8, 0x0C, 0x4E}));
  // Sonar 7 (slave 8) looks along -y at a wall 4.7 m away: no echo, 0.
  const Bytes reply = exchange({0x08, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0x53});
  ASSERT_EQ(reply.size(), 7u);
  EXPECT_EQ(reply[3], 0);
  EXPECT_EQ(reply[4], 0);
}

TEST_F(ModbusSensorBusDeviceTest, TheNearestRayOfTheConeWins) {
  // Sonar 1 (slave 2) at (0.30, 0.20) looks 45 degrees left; turned so that its cone's left edge
  // points straight at the wall at y = 1.30, that ray is the shortest: 1.10 m.
  const double edge_rad = 11.25 * kPi / 180.0;
  world_.set_base_pose({0.0, 0.0, kPi / 4.0 - edge_rad});
  const geometry::Pose2D sonar = geometry::compose(world_.base_pose(), {0.30, 0.20, kPi / 4.0});
  const Bytes reply = exchange({0x02, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xF9});
  ASSERT_EQ(reply.size(), 7u);
  EXPECT_EQ((reply[3] << 8) | reply[4], std::lround((1.30 - sonar.y) * 1000.0));
}

TEST_F(ModbusSensorBusDeviceTest, TheLimitSwitchIsDiscreteInputZero) {
  EXPECT_EQ(exchange({0x0A, 0x02, 0x00, 0x00, 0x00, 0x01, 0xB8, 0xB1}),
            (Bytes{0x0A, 0x02, 0x01, 0x00, 0xA3, 0xAC}));
  device_.set_limit_switch(true);
  EXPECT_EQ(exchange({0x0A, 0x02, 0x00, 0x00, 0x00, 0x01, 0xB8, 0xB1}),
            (Bytes{0x0A, 0x02, 0x01, 0x01, 0x62, 0x6C}));
}

TEST_F(ModbusSensorBusDeviceTest, RepliesComeAfterTheSilenceOneByteTimeApart) {
  device_.receive(Bytes{0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCA}, 1.0);
  const double start_s = 1.0 + kSilence_s;
  EXPECT_TRUE(device_.transmit(start_s + 0.5 * kByte_s).empty());
  EXPECT_EQ(device_.transmit(start_s + 1.5 * kByte_s), (Bytes{0x01}));
  EXPECT_EQ(device_.transmit(start_s + 6.5 * kByte_s), (Bytes{0x04, 0x02, 0x00, 0x00, 0xB9}));
  EXPECT_EQ(device_.transmit(start_s + 7.5 * kByte_s), (Bytes{0x30}));
  EXPECT_TRUE(device_.transmit(kLater_s * 10).empty());
}

TEST_F(ModbusSensorBusDeviceTest, ASecondReplyWaitsForTheLine) {
  // Two requests in one burst: the second reply follows the first, it does not overlap it.
  Bytes both = {0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCA};
  both.insert(both.end(), {0x0A, 0x02, 0x00, 0x00, 0x00, 0x01, 0xB8, 0xB1});
  device_.receive(both, 1.0);
  EXPECT_EQ(device_.transmit(1.0 + kSilence_s + 7.5 * kByte_s).size(), 7u);
  EXPECT_EQ(device_.transmit(1.0 + kSilence_s + 13.5 * kByte_s).size(), 6u);
}

TEST_F(ModbusSensorBusDeviceTest, GarbageBeforeARequestIsSkipped) {
  Bytes bytes = {0xFF, 0x00, 0x13, 0x10, 0x37, 0x01};
  bytes.insert(bytes.end(), {0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCA});
  EXPECT_EQ(exchange(bytes), (Bytes{0x01, 0x04, 0x02, 0x00, 0x00, 0xB9, 0x30}));
  EXPECT_EQ(device_.discarded_bytes(), 6u);
}

TEST_F(ModbusSensorBusDeviceTest, ARequestSplitOverSeveralReadsIsAnswered) {
  device_.receive(Bytes{0x01, 0x04, 0x00}, 0.0);
  device_.receive(Bytes{0x00, 0x00}, 0.001);
  EXPECT_TRUE(device_.transmit(0.5).empty());
  device_.receive(Bytes{0x01, 0x31, 0xCA}, 1.0);
  EXPECT_EQ(device_.transmit(2.0), (Bytes{0x01, 0x04, 0x02, 0x00, 0x00, 0xB9, 0x30}));
}

TEST_F(ModbusSensorBusDeviceTest, ABadCrcIsIgnoredAndTheNextRequestAnswered) {
  EXPECT_TRUE(exchange({0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCB}).empty());
  EXPECT_EQ(device_.requests(), 0u);
  EXPECT_EQ(exchange({0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCA}),
            (Bytes{0x01, 0x04, 0x02, 0x00, 0x00, 0xB9, 0x30}));
}

TEST_F(ModbusSensorBusDeviceTest, AnAbsentNodeAndABroadcastGetNoReply) {
  device_.set_node_present(1, false);
  EXPECT_TRUE(exchange({0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCA}).empty());
  EXPECT_EQ(device_.requests(), 1u);  // heard and framed, just not answered
  device_.set_node_present(1, true);
  EXPECT_EQ(exchange({0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCA}).size(), 7u);
  // Broadcast (slave 0) and a slave that is not on this bus (11).
  EXPECT_TRUE(exchange({0x00, 0x04, 0x00, 0x00, 0x00, 0x01, 0x30, 0x1B}).empty());
  EXPECT_TRUE(exchange({0x0B, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0x60}).empty());
  EXPECT_THROW(device_.set_node_present(11, false), std::invalid_argument);
}

TEST_F(ModbusSensorBusDeviceTest, ExceptionsForAnAddressAQuantityOrAFunctionItHasNot) {
  // Register 1 of the compass: illegal data address.
  EXPECT_EQ(exchange({0x01, 0x04, 0x00, 0x01, 0x00, 0x01, 0x60, 0x0A}),
            (Bytes{0x01, 0x84, 0x02, 0xC2, 0xC1}));
  // A quantity of 0: illegal data value.
  EXPECT_EQ(exchange({0x01, 0x04, 0x00, 0x00, 0x00, 0x00, 0xF0, 0x0A}),
            (Bytes{0x01, 0x84, 0x03, 0x03, 0x01}));
  // Write single register: illegal function.
  EXPECT_EQ(exchange({0x01, 0x06, 0x00, 0x00, 0x00, 0x01, 0x48, 0x0A}),
            (Bytes{0x01, 0x86, 0x01, 0x83, 0xA0}));
  // The limit switch has no registers.
  EXPECT_EQ(exchange({0x0A, 0x04, 0x00, 0x00, 0x00, 0x01, 0x30, 0xB1}),
            (Bytes{0x0A, 0x84, 0x02, 0xB3, 0x03}));
}

TEST_F(ModbusSensorBusDeviceTest, AWriteOfSeveralRegistersIsFramedByItsByteCount) {
  Bytes request = {0x01, 0x10, 0x00, 0x00, 0x00, 0x02, 0x04, 0x00, 0x0A, 0x01, 0x02};
  const std::uint16_t crc = modbus_crc16(request);
  request.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  request.push_back(static_cast<std::uint8_t>(crc >> 8));
  EXPECT_EQ(exchange(request), (Bytes{0x01, 0x90, 0x01, 0x8D, 0xC0}));
}

TEST_F(ModbusSensorBusDeviceTest, BadChecksumsSpoilEveryReplysCrc) {
  device_.set_bad_checksums(true);
  EXPECT_EQ(exchange({0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCA}),
            (Bytes{0x01, 0x04, 0x02, 0x00, 0x00, 0x46, 0xCF}));
  device_.set_bad_checksums(false);
  EXPECT_EQ(exchange({0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCA}),
            (Bytes{0x01, 0x04, 0x02, 0x00, 0x00, 0xB9, 0x30}));
}

TEST_F(ModbusSensorBusDeviceTest, TimeNeverRunsBackwards) {
  EXPECT_TRUE(device_.transmit(5.0).empty());
  device_.receive(Bytes{0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCA}, 1.0);  // taken as 5.0
  EXPECT_TRUE(device_.transmit(5.0 + kSilence_s + 0.5 * kByte_s).empty());
  EXPECT_EQ(device_.transmit(5.1).size(), 7u);
}

TEST(ModbusSensorBusDevice, NoiseIsAboutOneDegreeAndSeeded) {
  testing::BoxWorld world(-5.0, 5.0, -5.0, 5.0);
  world.set_base_pose({0.0, 0.0, -1.0});  // 57.3 degrees on the compass
  const auto headings = [&world](std::uint64_t seed) {
    ModbusSensorBusDevice device(world, ModbusSensorBusOptions{}, seed);
    std::vector<double> degrees;
    for (int i = 0; i < 400; ++i) {
      device.receive(Bytes{0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0x31, 0xCA}, i);
      const Bytes reply = device.transmit(i + 0.5);
      degrees.push_back(((reply.at(3) << 8) | reply.at(4)) / 10.0);
    }
    return degrees;
  };
  const std::vector<double> degrees = headings(3);
  EXPECT_EQ(degrees, headings(3));
  EXPECT_NE(degrees, headings(4));
  double sum = 0.0;
  double sum_sq = 0.0;
  for (const double value : degrees) {
    sum += value;
    sum_sq += value * value;
  }
  const double mean = sum / degrees.size();
  const double sigma = std::sqrt(sum_sq / degrees.size() - mean * mean);
  EXPECT_NEAR(mean, 180.0 / kPi, 0.2);
  EXPECT_NEAR(sigma, 1.0, 0.15);
}

TEST(ModbusSensorBusDevice, RejectsABusItCannotModel) {
  testing::BoxWorld world(-1.0, 1.0, -1.0, 1.0);
  ModbusSensorBusOptions repeated;
  repeated.limit_switch_node = 2;
  EXPECT_THROW(ModbusSensorBusDevice(world, repeated, 1), std::invalid_argument);
  ModbusSensorBusOptions broadcast;
  broadcast.compass_node = 0;
  EXPECT_THROW(ModbusSensorBusDevice(world, broadcast, 1), std::invalid_argument);
  ModbusSensorBusOptions poses;
  poses.sonar_poses.pop_back();
  EXPECT_THROW(ModbusSensorBusDevice(world, poses, 1), std::invalid_argument);
  ModbusSensorBusOptions baud;
  baud.baud = 0;
  EXPECT_THROW(ModbusSensorBusDevice(world, baud, 1), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::emulate
