#include "tools/emulate/devices/dashgo_base_device.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "drivers/protocol/line_framer.h"
#include "drivers/protocol/ros_arduino_bridge.h"

namespace mobot::emulate {
namespace {

namespace bridge = protocol::arduino_bridge;

// An empty floor with a wall at x = wall_x_m.
class WallWorld final : public EmulatedWorld {
 public:
  explicit WallWorld(double wall_x_m) : wall_x_m_(wall_x_m) {}
  geometry::Pose2D base_pose() const override { return pose_; }
  void set_base_pose(const geometry::Pose2D& pose) override { pose_ = pose; }
  std::optional<double> cast_ray(geometry::Point2D from, double angle_rad, double,
                                 double max_range_m) const override {
    const double dx = std::cos(angle_rad);
    if (dx <= 1e-9) return std::nullopt;
    const double range_m = (wall_x_m_ - from.x) / dx;
    if (range_m < 0.0 || range_m > max_range_m) return std::nullopt;
    return range_m;
  }

 private:
  double wall_x_m_;
  geometry::Pose2D pose_;
};

class DashgoBaseDeviceTest : public ::testing::Test {
 protected:
  // Sends a command at `now_s` and returns the reply line once its bytes have gone out.
  std::string ask(const std::string& command) {
    device_.receive({reinterpret_cast<const std::uint8_t*>(command.data()), command.size()},
                    now_s_);
    std::vector<std::string> lines;
    for (int i = 0; i < 100 && lines.empty(); ++i) {
      now_s_ += 0.0005;
      const std::vector<std::uint8_t> out = device_.transmit(now_s_);
      framer_.feed(out, lines);
    }
    return lines.empty() ? std::string("<nothing>") : lines.front();
  }
  void run_for(double seconds) {
    now_s_ += seconds;
    device_.transmit(now_s_);
  }

  WallWorld world_{5.0};
  DashgoBaseDevice device_{{.wheel_speed_noise_fraction = 0.0, .sonars_in_base = {{0.2, 0.0, 0.0}}},
                           world_};
  protocol::LineFramer framer_;
  double now_s_ = 0.0;
};

TEST_F(DashgoBaseDeviceTest, AnswersAsTheSketchDoes) {
  EXPECT_EQ(ask("b\r"), "115200");
  EXPECT_EQ(ask("u 20:12:0:50\r"), "OK");
  EXPECT_EQ(ask("r\r"), "OK");
  EXPECT_EQ(ask("e\r"), "0 0");
  EXPECT_EQ(ask("v\r"), "124");
  EXPECT_EQ(ask("j\r"), "0");
  device_.set_estop_button(true);
  EXPECT_EQ(ask("j\r"), "1");
  EXPECT_EQ(ask("x\r"), "Invalid Command");
  EXPECT_EQ(ask("m 1\r"), "Invalid Command");
}

TEST_F(DashgoBaseDeviceTest, TheReplyTakesItsTimeOnTheLine) {
  const std::string command = "b\r";
  device_.receive({reinterpret_cast<const std::uint8_t*>(command.data()), command.size()}, 0.0);
  // "115200\r\n" is 8 bytes: 0.69 ms at 115200 baud, after the sketch's 1 ms.
  EXPECT_TRUE(device_.transmit(0.0015).empty());
  EXPECT_EQ(device_.transmit(0.0018).size(), 8U);
}

TEST_F(DashgoBaseDeviceTest, WheelsTurnAtTheCommandedTicksPerFrameAndMoveTheBase) {
  ASSERT_EQ(ask("m 40 40\r"), "OK");  // one wheel turn per second
  run_for(2.0);
  const std::string counts = ask("e\r");
  const auto values = bridge::parse_integers(counts, 2);
  ASSERT_TRUE(values);
  // 2 s at 1200 ticks/s, less the 0.1 s spin-up.
  EXPECT_NEAR(static_cast<double>((*values)[0]), 2280.0, 30.0);
  EXPECT_EQ((*values)[0], (*values)[1]);
  const double travelled_m = 2280.0 / 1200.0 * 2.0 * std::numbers::pi * 0.064;
  EXPECT_NEAR(world_.base_pose().x, travelled_m, 0.02);
  EXPECT_NEAR(world_.base_pose().y, 0.0, 1e-9);
}

TEST_F(DashgoBaseDeviceTest, OppositeWheelsTurnTheBaseInPlace) {
  ASSERT_EQ(ask("m -20 20\r"), "OK");
  run_for(1.0);
  EXPECT_GT(world_.base_pose().theta, 0.5);
  EXPECT_NEAR(world_.base_pose().x, 0.0, 1e-9);
}

TEST_F(DashgoBaseDeviceTest, StopsByItselfTwoSecondsAfterTheLastSpeedCommand) {
  ASSERT_EQ(ask("m 40 40\r"), "OK");
  run_for(3.0);
  const double x_m = world_.base_pose().x;
  run_for(1.0);
  EXPECT_NEAR(world_.base_pose().x, x_m, 1e-4);
}

TEST_F(DashgoBaseDeviceTest, CountsWrapAt16Bits) {
  ASSERT_EQ(ask("m 1000 1000\r"), "OK");  // 30000 ticks/s
  run_for(1.5);
  const auto values = bridge::parse_integers(ask("e\r"), 2);
  ASSERT_TRUE(values);
  EXPECT_GE((*values)[0], -32768);
  EXPECT_LE((*values)[0], 32767);
  EXPECT_GT(device_.left_ticks(), 32768.0);
}

TEST_F(DashgoBaseDeviceTest, StopsAtAWallWhileTheWheelsSpin) {
  ASSERT_EQ(ask("m 40 40\r"), "OK");
  for (int i = 0; i < 40; ++i) {
    ask("m 40 40\r");
    run_for(0.5);
  }
  EXPECT_LT(world_.base_pose().x, 5.0 - 0.2 + 1e-6);
  EXPECT_GT(device_.left_ticks(), 20000.0);
}

TEST_F(DashgoBaseDeviceTest, SonarsReportCentimetresAndZeroWithoutEcho) {
  world_.set_base_pose({4.5, 0.0, 0.0});
  EXPECT_EQ(ask("p\r"), "30");  // the sonar at x + 0.2 sees the wall 0.3 m ahead
  world_.set_base_pose({0.0, 0.0, 0.0});
  EXPECT_EQ(ask("p\r"), "0");
}

TEST_F(DashgoBaseDeviceTest, BadChecksumsManglesEveryReply) {
  device_.set_bad_checksums(true);
  const std::string reply = ask("e\r");
  EXPECT_FALSE(bridge::parse_integers(reply, 2)) << reply;
}

}  // namespace
}  // namespace mobot::emulate
