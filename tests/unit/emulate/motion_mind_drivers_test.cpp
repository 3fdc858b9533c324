// R1's Motion Mind drivers (the wheels and the tilt axis on one line) against the emulated boards
// on a pseudo-terminal: the real serial code, the real protocol, and each fault the line can have.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <iostream>
#include <limits>
#include <mutex>
#include <numbers>
#include <thread>

#include "drivers/hardware/motion_mind_base.h"
#include "drivers/hardware/motion_mind_devices.h"
#include "drivers/hardware/motion_mind_line.h"
#include "drivers/hardware/motion_mind_tilt_laser.h"
#include "tests/unit/emulate/line_harness.h"
#include "tools/emulate/devices/motion_mind_device.h"

namespace mobot::emulate {
namespace {

namespace hw = drivers::hardware;
namespace mm = protocol::motion_mind;
using testing::eventually;

constexpr std::uint8_t kLeft = 1;
constexpr std::uint8_t kRight = 2;
constexpr std::uint8_t kTilt = 3;
constexpr double kTiltCountsPerDegree = 200.0;
constexpr double kTiltStartDeg = 10.0;
constexpr double kRadPerDeg = std::numbers::pi / 180.0;

// The boards' line with the wheels moving the world, as the emulated robot couples them.
class CoupledBus final : public EmulatedDevice {
 public:
  CoupledBus(const MotionMindBusOptions& options, EmulatedWorld& world,
             const MotionMindBaseGeometry& geometry)
      : bus_(options), coupling_(bus_, kLeft, kRight, world, geometry) {}

  std::string_view name() const override { return bus_.name(); }
  void receive(std::span<const std::uint8_t> bytes, double now_s) override {
    bus_.receive(bytes, now_s);
  }
  std::vector<std::uint8_t> transmit(double now_s) override {
    std::vector<std::uint8_t> out = bus_.transmit(now_s);
    coupling_.update();
    return out;
  }
  void set_bad_checksums(bool on) override { bus_.set_bad_checksums(on); }
  const MotionMindBus& bus() const { return bus_; }

 private:
  MotionMindBus bus_;
  MotionMindBaseCoupling coupling_;
};

// The SICK's driver as the tilt sees it: scans fed in by the test, on the test's thread.
class FakeLaser final : public hw::LaserScanSource {
 public:
  void add_listener(Listener listener) override { listener_ = std::move(listener); }  // one here
  drivers::DeviceStatus status() const override {
    const std::lock_guard lock(mutex_);
    return status_;
  }
  void set_status(drivers::DeviceStatus status) {
    const std::lock_guard lock(mutex_);
    status_ = std::move(status);
  }
  void feed(const msgs::LaserScan& scan) {
    if (listener_) listener_(scan, std::chrono::steady_clock::now());
  }

 private:
  Listener listener_;
  mutable std::mutex mutex_;
  drivers::DeviceStatus status_;
};

msgs::LaserScan laser_scan(float first_range_m) {
  msgs::LaserScan scan;
  scan.angle_min_rad = static_cast<float>(-std::numbers::pi / 2.0);
  scan.angle_increment_rad = static_cast<float>(kRadPerDeg);
  scan.range_min_m = 0.4F;
  scan.range_max_m = 80.0F;
  scan.ranges_m.assign(181, 5.0F);
  scan.ranges_m.front() = first_range_m;
  return scan;
}

MotionMindBusOptions r1_boards(std::int32_t left_initial_counts, bool tilt_switch) {
  MotionMindBusOptions options;
  MotionMindBoardOptions left;
  left.address = kLeft;
  left.initial_position_counts = left_initial_counts;
  MotionMindBoardOptions right;
  right.address = kRight;
  MotionMindBoardOptions tilt;
  tilt.address = kTilt;
  tilt.counts_per_rev = 360.0 * kTiltCountsPerDegree;
  if (tilt_switch) tilt.tilt = MotionMindTiltOptions{kTiltCountsPerDegree, -5.0, kTiltStartDeg};
  options.boards = {left, right, tilt};
  return options;
}

class MotionMindDriversTest : public ::testing::Test {
 protected:
  ~MotionMindDriversTest() override {
    tilt_.reset();
    base_.reset();
    if (line_) line_->stop();
    line_.reset();
    harness_.reset();
  }

  // R1's boards on the emulated line; the right motor is mirrored.
  void make_line(std::int32_t left_initial_counts = 0, bool tilt_switch = true) {
    auto device = std::make_unique<CoupledBus>(r1_boards(left_initial_counts, tilt_switch), world_,
                                               MotionMindBaseGeometry{0.60, 0.075, 1, -1});
    model_ = device.get();
    harness_ = std::make_unique<testing::LineHarness>(std::move(device));
  }

  // The drivers on the line: the wheels, and the tilt unless `wheels_only`.
  void make_drivers(bool wheels_only = false) {
    hw::MotionMindLineOptions options;
    options.serial.device = harness_->path().string();
    line_ = std::make_shared<hw::MotionMindLine>(options);
    const auto left = line_->add_board({kLeft, mm::kR1WheelCountsPerRev, mm::r1_wheel_setup()});
    const auto right = line_->add_board({kRight, mm::kR1WheelCountsPerRev, mm::r1_wheel_setup()});
    base_ = std::make_unique<hw::MotionMindBase>(line_, left, right, 1, -1);
    if (!wheels_only) {
      tilt_board_ = line_->add_board(hw::motion_mind_tilt_board(kTilt, kTiltCountsPerDegree));
      hw::MotionMindTiltLaserOptions tilt_options;
      tilt_options.counts_per_degree = kTiltCountsPerDegree;
      tilt_options.home_speed_dps = home_speed_dps_;
      tilt_options.sensor_in_base = {0.2, 0.0, 0.0};
      tilt_options.sensor_height_m = 0.4;
      tilt_ = std::make_unique<hw::MotionMindTiltLaser>(line_, tilt_board_, laser_, tilt_options);
    }
  }

  void start() {
    if (!line_) make_drivers();
    line_->start();
  }

  bool ok() const { return line_->health().status().ok; }
  std::string reason() const { return line_->health().status().reason; }

  template <class T>
  T on_bus(const std::function<T(const MotionMindBus&)>& read) {
    T value{};
    harness_->with_line([&](DeviceLine&) { value = read(model_->bus()); });
    return value;
  }
  double tilt_pitch_deg() {
    return on_bus<double>([](const MotionMindBus& bus) { return *bus.tilt_pitch_deg(kTilt); });
  }

  // The encoders as the control loop reads them, once new counts came.
  msgs::WheelEncoders next_encoders() {
    std::optional<msgs::WheelEncoders> encoders;
    EXPECT_TRUE(
        eventually([&] { return (encoders = base_->read_encoders(0.0)).has_value(); }, 1.0));
    return encoders.value_or(msgs::WheelEncoders{});
  }

  testing::EmptyWorld world_;
  FakeLaser laser_;
  CoupledBus* model_ = nullptr;
  std::unique_ptr<testing::LineHarness> harness_;
  std::shared_ptr<hw::MotionMindLine> line_;
  std::unique_ptr<hw::MotionMindBase> base_;
  hw::MotionMindLine::BoardId tilt_board_ = 0;
  double home_speed_dps_ = 10.0;
  std::unique_ptr<hw::MotionMindTiltLaser> tilt_;
};

TEST_F(MotionMindDriversTest, WheelCommandsMoveTheCountsAtTheRightRate) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0)) << reason();
  // 2 rad/s on a 38000-count wheel: 12096 counts/s; the mirrored right motor still counts up.
  base_->set_wheel_command({2.0, 2.0});
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const msgs::WheelEncoders first = next_encoders();
  const auto first_at = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const msgs::WheelEncoders last = next_encoders();
  const double elapsed_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - first_at).count();
  const double expected = 2.0 / (2.0 * std::numbers::pi) * mm::kR1WheelCountsPerRev;
  // The counts are up to a cycle older than the moment they are taken.
  EXPECT_NEAR((last.left_ticks - first.left_ticks) / elapsed_s, expected, 0.08 * expected);
  EXPECT_NEAR((last.right_ticks - first.right_ticks) / elapsed_s, expected, 0.08 * expected);
  // Straight ahead at 0.15 m/s.
  geometry::Pose2D pose;
  harness_->with_line([&](DeviceLine&) { pose = world_.base_pose(); });
  EXPECT_GT(pose.x, 0.3);
  EXPECT_NEAR(pose.y, 0.0, 0.05);

  // A slow turn below one set-point unit per wheel (0.02 rad/s = 0.6 units): the dither makes
  // the boards average it.
  base_->set_wheel_command({-0.02, 0.02});
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const msgs::WheelEncoders slow_first = next_encoders();
  const auto slow_at = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const msgs::WheelEncoders slow_last = next_encoders();
  const double slow_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - slow_at).count();
  const double slow_expected = 0.02 / (2.0 * std::numbers::pi) * mm::kR1WheelCountsPerRev;
  EXPECT_NEAR((slow_last.right_ticks - slow_first.right_ticks) / slow_s, slow_expected,
              0.25 * slow_expected);
  EXPECT_NEAR((slow_last.left_ticks - slow_first.left_ticks) / slow_s, -slow_expected,
              0.25 * slow_expected);

  // Stopped, the counts are the boards' own (the right one's negated).
  base_->set_wheel_command({0.0, 0.0});
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const msgs::WheelEncoders stopped = next_encoders();
  const auto left_raw =
      on_bus<std::int32_t>([](const MotionMindBus& bus) { return *bus.position_register(kLeft); });
  const auto right_raw =
      on_bus<std::int32_t>([](const MotionMindBus& bus) { return *bus.position_register(kRight); });
  EXPECT_NEAR(static_cast<double>(stopped.left_ticks), left_raw, 3.0);
  EXPECT_NEAR(static_cast<double>(stopped.right_ticks), -right_raw, 3.0);
  EXPECT_EQ(line_->health().checksum_errors(), 0U);
  EXPECT_GT(line_->health().frames(), 50U);
}

TEST_F(MotionMindDriversTest, ReadEncodersReturnsEachCountOnce) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0)) << reason();
  next_encoders();
  // Far faster than the line cycles: most calls find nothing new.
  int fresh = 0;
  for (int i = 0; i < 100; ++i) {
    if (base_->read_encoders(0.0)) ++fresh;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_GT(fresh, 0);
  EXPECT_LT(fresh, 30);
}

TEST_F(MotionMindDriversTest, CountsUnwrapPastThe32BitPosition) {
  make_line(std::numeric_limits<std::int32_t>::max() - 3000);
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0)) << reason();
  const std::int64_t start_ticks = next_encoders().left_ticks;
  base_->set_wheel_command({2.0, 2.0});
  EXPECT_TRUE(eventually(
      [&] {
        const auto encoders = base_->read_encoders(0.0);
        return encoders && encoders->left_ticks > start_ticks + 6000;
      },
      2.0));
  EXPECT_GT(start_ticks, std::numeric_limits<std::int32_t>::max() - 3010);
}

TEST_F(MotionMindDriversTest, TheLineCyclesAsFastAsItAllows) {
  make_line();
  make_drivers(/*wheels_only=*/true);
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0)) << reason();
  auto measure = [&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const std::uint64_t before = line_->cycles();
    const auto at = std::chrono::steady_clock::now();
    std::this_thread::sleep_for(std::chrono::seconds(2));
    return static_cast<double>(line_->cycles() - before) /
           std::chrono::duration<double>(std::chrono::steady_clock::now() - at).count();
  };
  const double two_boards_hz = measure();
  line_->stop();
  base_.reset();
  line_.reset();
  make_drivers();
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0)) << reason();
  const double three_boards_hz = measure();
  std::cout << "Motion Mind line at 19200 baud: 2 boards " << two_boards_hz << " Hz, 3 boards "
            << three_boards_hz << " Hz (smoothed " << line_->cycle_rate_hz() << " Hz)\n";
  RecordProperty("two_boards_hz", std::to_string(two_boards_hz));
  RecordProperty("three_boards_hz", std::to_string(three_boards_hz));
  // One exchange is ~13 ms on the emulator (5 + 6 bytes at 19200, the 5 ms gap, a 2 ms delay).
  EXPECT_GT(two_boards_hz, 20.0);
  EXPECT_GT(three_boards_hz, 14.0);
  EXPECT_GT(two_boards_hz, three_boards_hz);
}

TEST_F(MotionMindDriversTest, TheTiltHomesAndSweepsWithIncreasingPitch) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0)) << reason();
  EXPECT_TRUE(tilt_->status().ok) << tilt_->status().reason;
  // A short mode: 20 scans in 2 s (12.5 deg/s), the laser at the mode's 10 Hz.
  const perception::SweepMode mode{2.0, 1.0, 20};
  std::jthread laser_thread([&](const std::stop_token& stop) {
    for (int i = 0; !stop.stop_requested(); ++i) {
      laser_.feed(laser_scan(static_cast<float>(1.0 + 0.01 * (i % 100))));
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
  tilt_->start(mode, 0.0);
  // Down from +10 deg at 10 deg/s: no scan before the switch.
  EXPECT_TRUE(eventually([&] { return tilt_pitch_deg() <= -4.5; }, 3.0)) << tilt_pitch_deg();
  std::vector<msgs::TiltScan> scans;
  ASSERT_TRUE(eventually(
      [&] {
        while (auto scan = tilt_->poll(1.0)) scans.push_back(std::move(*scan));
        return scans.size() >= static_cast<std::size_t>(mode.scans);
      },
      6.0))
      << scans.size();
  laser_thread.request_stop();
  laser_thread.join();
  ASSERT_EQ(scans.size(), 20U);
  EXPECT_FALSE(tilt_->poll(2.0));
  ASSERT_TRUE(tilt_->limit_counts());

  const perception::TiltRange range;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const msgs::TiltScan& scan = scans[i];
    EXPECT_NEAR(scan.pitch_rad, range.min_pitch_rad + i * range.span_rad() / 20.0, 1e-12);
    if (i > 0) {
      EXPECT_GT(scan.pitch_rad, scans[i - 1].pitch_rad);
    }
    EXPECT_DOUBLE_EQ(scan.stamp_s, 1.0);
    // -pi/2 (right) .. pi/2 of the laser: 0 .. pi of the sweep.
    EXPECT_NEAR(scan.bearing_min_rad, 0.0, 1e-6);
    EXPECT_NEAR(scan.bearing_step_rad, kRadPerDeg, 1e-6);
    EXPECT_EQ(scan.ranges_m.size(), 181U);
    EXPECT_FLOAT_EQ(scan.range_max_m, 80.0F);
    EXPECT_DOUBLE_EQ(scan.sensor_in_base.x, 0.2);
    EXPECT_DOUBLE_EQ(scan.sensor_height_m, 0.4);
  }
  // The sweep over, the laser goes back level by itself, for the planar scans.
  EXPECT_TRUE(eventually([&] { return std::abs(tilt_pitch_deg()) < 0.3; }, 4.0))
      << tilt_pitch_deg();
  EXPECT_TRUE(tilt_->status().ok);
}

TEST_F(MotionMindDriversTest, TheTiltHoldsAtTheTopWhenTheScansStopAndStopParksItLevel) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0)) << reason();
  // The laser stops after the first five scans of the sweep.
  std::atomic<int> to_feed{5};
  std::jthread laser_thread([&](const std::stop_token& stop) {
    while (!stop.stop_requested()) {
      if (to_feed > 0 && tilt_->limit_counts()) {
        laser_.feed(laser_scan(1.0F));
        --to_feed;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
  tilt_->start({2.0, 1.0, 20}, 0.0);
  // The axis rises through the span and holds the switch's count plus the span (its pitch:
  // the switch shows 2 periods, 0.1 deg, past -5 deg).
  ASSERT_TRUE(eventually([&] { return std::abs(tilt_pitch_deg() - 20.0) < 0.3; }, 6.0))
      << tilt_pitch_deg();
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const double top_deg = tilt_pitch_deg();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_NEAR(tilt_pitch_deg(), top_deg, 0.05);
  EXPECT_NEAR(top_deg, 20.0, 0.3);
  int scans = 0;
  while (tilt_->poll(0.0)) ++scans;
  EXPECT_EQ(scans, 5);

  tilt_->stop();
  EXPECT_TRUE(eventually([&] { return std::abs(tilt_pitch_deg()) < 0.3; }, 4.0))
      << tilt_pitch_deg();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_NEAR(tilt_pitch_deg(), 0.0, 0.3);
  EXPECT_FALSE(tilt_->poll(0.0));
}

TEST_F(MotionMindDriversTest, ScansBeforeTheSwitchOrAheadOfTheModeAreSkipped) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0)) << reason();
  // The laser at 40 Hz, four times the mode's rate: every fourth scan or so is taken.
  const perception::SweepMode mode{1.0, 1.0, 10};
  std::jthread laser_thread([&](const std::stop_token& stop) {
    while (!stop.stop_requested()) {
      laser_.feed(laser_scan(1.0F));
      std::this_thread::sleep_for(std::chrono::milliseconds(25));
    }
  });
  tilt_->start(mode, 0.0);
  std::vector<msgs::TiltScan> scans;
  const auto started = std::chrono::steady_clock::now();
  ASSERT_TRUE(eventually(
      [&] {
        while (auto scan = tilt_->poll(0.0)) scans.push_back(std::move(*scan));
        return scans.size() >= 10U;
      },
      6.0));
  const double took_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  // Homing (1.5 s) and the mode's 1 s, not 10 scans at 40 Hz after the switch.
  EXPECT_GT(took_s, 2.0);
  EXPECT_LT(took_s, 3.5);
}

TEST_F(MotionMindDriversTest, ASwitchThatNeverClosesStopsTheSeek) {
  make_line(0, /*tilt_switch=*/false);
  home_speed_dps_ = 40.0;
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0)) << reason();
  std::jthread laser_thread([&](const std::stop_token& stop) {
    while (!stop.stop_requested()) {
      laser_.feed(laser_scan(1.0F));
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
  tilt_->start({2.0, 1.0, 20}, 0.0);
  // The range and the 10 deg margin (35 deg) at 40 deg/s, then the axis is stopped.
  EXPECT_TRUE(eventually([&] { return tilt_->status().reason == "limit_switch"; }, 2.0))
      << tilt_->status().reason;
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  // The shaft's angle is the pitch here (360 x counts per degree a turn): 35 deg and the stop,
  // which comes at the driver's next poll of the line. That poll runs every 25-40 ms, but on a
  // loaded machine a thread can wait far longer: up to a quarter of a second (10 deg at 40 deg/s)
  // is taken as the stop, not as a failure of it.
  const double travel_deg =
      on_bus<double>([](const MotionMindBus& bus) { return *bus.shaft_angle_rad(kTilt); }) /
      kRadPerDeg;
  EXPECT_LE(travel_deg, -34.0);
  EXPECT_GE(travel_deg, -45.0);
  EXPECT_NEAR(
      on_bus<double>([](const MotionMindBus& bus) { return *bus.shaft_speed_radps(kTilt); }), 0.0,
      0.01);
  EXPECT_FALSE(tilt_->poll(0.0));
  EXPECT_TRUE(ok());
  // Without a switch found there is no level to park at: stop() only stops the axis.
  tilt_->stop();
  EXPECT_FALSE(tilt_->limit_counts());
}

TEST_F(MotionMindDriversTest, TheTiltIsAsWellAsTheWorseOfLineAndLaser) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0)) << reason();
  EXPECT_TRUE(tilt_->status().ok);
  laser_.set_status({false, "silent"});
  EXPECT_EQ(tilt_->status().reason, "silent");
  harness_->with_line([&](DeviceLine& line) { line.set_fault(LineFault::kUnplug, 0.0, 0.0); });
  EXPECT_TRUE(eventually([&] { return tilt_->status().reason == "missing"; }, 1.0));
  EXPECT_EQ(base_->status().reason, "missing");
  harness_->with_line([&](DeviceLine& line) { line.clear_fault(); });
  EXPECT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
  EXPECT_EQ(tilt_->status().reason, "silent");
  laser_.set_status({});
  EXPECT_TRUE(tilt_->status().ok);
}

TEST_F(MotionMindDriversTest, AMissingDeviceIsMissingUntilItAppears) {
  make_line();
  harness_->with_line([&](DeviceLine& line) { line.set_fault(LineFault::kUnplug, 0.0, 0.0); });
  start();
  EXPECT_TRUE(eventually([&] { return reason() == "missing"; }, 1.0)) << reason();
  harness_->with_line([&](DeviceLine& line) { line.clear_fault(); });
  EXPECT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
}

TEST_F(MotionMindDriversTest, ABoardThatIsNotThereSilencesTheLine) {
  make_line();
  hw::MotionMindLineOptions options;
  options.serial.device = harness_->path().string();
  line_ = std::make_shared<hw::MotionMindLine>(options);
  line_->add_board({kLeft, mm::kR1WheelCountsPerRev, mm::r1_wheel_setup()});
  line_->add_board({7, mm::kR1WheelCountsPerRev, mm::r1_wheel_setup()});
  line_->start();
  EXPECT_TRUE(eventually([&] { return reason() == "silent"; }, 1.0)) << reason();
}

TEST_F(MotionMindDriversTest, EachLineFaultIsReportedAndRecoveredFrom) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0)) << reason();
  base_->set_wheel_command({1.0, 1.0});
  const std::vector<std::pair<LineFault, std::string>> faults{
      {LineFault::kUnplug, "missing"},  {LineFault::kDrop, "silent"},
      {LineFault::kStall, "silent"},    {LineFault::kChecksum, "checksum"},
      {LineFault::kGarbage, "garbage"},
  };
  for (const auto& [fault, expected] : faults) {
    harness_->with_line([&](DeviceLine& line) { line.set_fault(fault, harness_->seconds(), 0); });
    EXPECT_TRUE(eventually([&] { return !ok(); }, 1.0)) << expected;
    // Noise reads as no reply or as replies that fail their checksum: either way not ok.
    if (fault != LineFault::kGarbage) {
      EXPECT_EQ(reason(), expected);
    }
    harness_->with_line([&](DeviceLine& line) { line.clear_fault(); });
    EXPECT_TRUE(eventually([&] { return ok(); }, 4.0)) << expected << ": " << reason();
    // Counting again: the wheels move on.
    const std::int64_t before = next_encoders().left_ticks;
    EXPECT_TRUE(eventually(
        [&] {
          const auto encoders = base_->read_encoders(0.0);
          return encoders && encoders->left_ticks > before + 100;
        },
        1.0))
        << expected;
  }
  EXPECT_GE(line_->health().reconnects(), 5U);
  EXPECT_GE(line_->health().checksum_errors(), 3U);
}

TEST_F(MotionMindDriversTest, EverySessionEndsWithTheBoardsStopped) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0)) << reason();
  // Spinning on the spot (left wheel forward, right back): the mirrored right motor turns its
  // shaft the same way as the left.
  base_->set_wheel_command({2.0, -2.0});
  line_->set_velocity(tilt_board_, 5.0 * kRadPerDeg);
  const auto speed = [&](std::uint8_t address) {
    return on_bus<double>(
        [address](const MotionMindBus& bus) { return *bus.shaft_speed_radps(address); });
  };
  ASSERT_TRUE(eventually([&] { return speed(kLeft) > 1.9 && speed(kRight) > 1.9; }, 1.0));
  // Boards that go silent end the session, and they still hear the zero set-points that end it:
  // they do not run on through the back-off.
  harness_->with_line([&](DeviceLine& line) { line.set_fault(LineFault::kDrop, 0.0, 0.0); });
  ASSERT_TRUE(eventually([&] { return !ok(); }, 1.0));
  EXPECT_TRUE(eventually(
      [&] {
        return std::abs(speed(kLeft)) < 0.01 && std::abs(speed(kRight)) < 0.01 &&
               std::abs(speed(kTilt)) < 0.01;
      },
      1.0))
      << speed(kLeft) << " " << speed(kRight) << " " << speed(kTilt);
  harness_->with_line([&](DeviceLine& line) { line.clear_fault(); });
  ASSERT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
  ASSERT_TRUE(eventually([&] { return speed(kLeft) > 1.9; }, 1.0));

  line_->stop();
  EXPECT_TRUE(eventually(
      [&] {
        return std::abs(speed(kLeft)) < 0.01 && std::abs(speed(kRight)) < 0.01 &&
               std::abs(speed(kTilt)) < 0.01;
      },
      1.0))
      << speed(kLeft) << " " << speed(kRight) << " " << speed(kTilt);
  EXPECT_EQ(reason(), "stopped");
}

TEST_F(MotionMindDriversTest, FiftyUnplugsLeakNoFileDescriptor) {
  make_line();
  make_drivers(/*wheels_only=*/true);
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 2.0)) << reason();
  const int before = testing::open_fd_count();
  for (int i = 0; i < 50; ++i) {
    harness_->with_line([&](DeviceLine& line) { line.set_fault(LineFault::kUnplug, 0.0, 0.0); });
    ASSERT_TRUE(eventually([&] { return !ok(); }, 1.0));
    harness_->with_line([&](DeviceLine& line) { line.clear_fault(); });
    ASSERT_TRUE(eventually([&] { return ok(); }, 4.0)) << i << ": " << reason();
  }
  EXPECT_EQ(testing::open_fd_count(), before);
}

// The factories, as the hardware backend calls them.
class MotionMindFactoryTest : public ::testing::Test {
 protected:
  void make(const char* role, const std::string& yaml,
            void (*factory)(hw::DeviceReader&, hw::HardwareAssembly&)) {
    hw::DeviceReader entry(YAML::Load(yaml), std::string("hardware.") + role);
    factory(entry, assembly_);
  }
  std::shared_ptr<hw::MotionMindLine> line(const std::string& device) {
    return std::static_pointer_cast<hw::MotionMindLine>(assembly_.shared_lines.at(device));
  }
  std::string error_of(const char* role, const std::string& yaml,
                       void (*factory)(hw::DeviceReader&, hw::HardwareAssembly&)) {
    try {
      make(role, yaml, factory);
    } catch (const drivers::BackendError& error) {
      return error.what();
    }
    return "";
  }

  sim::RobotProfile profile_ = sim::r1_profile();
  drivers::BackendOptions options_;
  FakeLaser laser_;
  hw::HardwareAssembly assembly_{profile_, options_, {}, {}, nullptr, {}};
};

TEST_F(MotionMindFactoryTest, TheBaseSharesItsLineWithTheTilt) {
  make("base", "{device: /dev/ttyUSB0}", hw::make_motion_mind_base);
  ASSERT_TRUE(assembly_.drivers.base);
  ASSERT_EQ(assembly_.devices.size(), 1U);
  EXPECT_EQ(assembly_.devices[0]->counters()[0].name, "base");
  EXPECT_EQ(line("/dev/ttyUSB0")->options().serial.baud, 19200U);
  EXPECT_EQ(line("/dev/ttyUSB0")->board(0).address, 1);
  EXPECT_EQ(line("/dev/ttyUSB0")->board(1).address, 2);
  EXPECT_DOUBLE_EQ(line("/dev/ttyUSB0")->board(0).counts_per_rev, 38000.0);

  assembly_.laser_source = &laser_;
  make("tilt", "{counts_per_degree: 200}", hw::make_motion_mind_tilt);
  ASSERT_TRUE(assembly_.drivers.tilt);
  EXPECT_EQ(assembly_.devices.size(), 1U);
  ASSERT_EQ(line("/dev/ttyUSB0")->board_count(), 3U);
  EXPECT_EQ(line("/dev/ttyUSB0")->board(2).address, 3);
  EXPECT_DOUBLE_EQ(line("/dev/ttyUSB0")->board(2).counts_per_rev, 72000.0);
  EXPECT_NEAR(assembly_.drivers.tilt->range().min_pitch_rad, -5.0 * kRadPerDeg, 1e-12);
}

TEST_F(MotionMindFactoryTest, TheTiltNamingTheBasesDeviceJoinsItsLine) {
  make("base", "{device: /dev/ttyUSB0, baud: 38400, left_address: 4, right_address: 5}",
       hw::make_motion_mind_base);
  assembly_.laser_source = &laser_;
  make("tilt", "{device: /dev/ttyUSB0, address: 6, counts_per_degree: 150}",
       hw::make_motion_mind_tilt);
  EXPECT_EQ(assembly_.devices.size(), 1U);
  EXPECT_EQ(line("/dev/ttyUSB0")->board_count(), 3U);
  EXPECT_NE(error_of("tilt", "{device: /dev/ttyUSB0, counts_per_degree: 1, baud: 19200}",
                     hw::make_motion_mind_tilt)
                .find("hardware.tilt.baud"),
            std::string::npos);
}

TEST_F(MotionMindFactoryTest, TheTiltOnAnotherDeviceHasALineOfItsOwn) {
  make("base", "{device: /dev/ttyUSB0}", hw::make_motion_mind_base);
  assembly_.laser_source = &laser_;
  make("tilt", "{device: /dev/ttyUSB1, counts_per_degree: 200}", hw::make_motion_mind_tilt);
  ASSERT_EQ(assembly_.devices.size(), 2U);
  EXPECT_EQ(assembly_.devices[1]->counters()[0].name, "tilt");
  EXPECT_EQ(line("/dev/ttyUSB0")->board_count(), 2U);
}

TEST_F(MotionMindFactoryTest, BadOptionsAreNamed) {
  EXPECT_NE(error_of("base", "{}", hw::make_motion_mind_base).find("hardware.base.device"),
            std::string::npos);
  EXPECT_NE(error_of("base", "{device: d, left_sign: 0}", hw::make_motion_mind_base)
                .find("hardware.base.left_sign"),
            std::string::npos);
  EXPECT_NE(error_of("base", "{device: d, right_address: 1}", hw::make_motion_mind_base)
                .find("hardware.base.right_address"),
            std::string::npos);
  EXPECT_NE(error_of("base", "{device: d, left_address: 99}", hw::make_motion_mind_base)
                .find("hardware.base.left_address"),
            std::string::npos);
  EXPECT_NE(error_of("base", "{device: d, wheel: 1}", hw::make_motion_mind_base)
                .find("hardware.base.wheel: unknown key"),
            std::string::npos);

  EXPECT_TRUE(assembly_.shared_lines.empty());
  make("base", "{device: /dev/ttyUSB0}", hw::make_motion_mind_base);
  EXPECT_NE(error_of("tilt", "{counts_per_degree: 200}", hw::make_motion_mind_tilt)
                .find("hardware.tilt: the tilt needs the laser"),
            std::string::npos);
  assembly_.laser_source = &laser_;
  EXPECT_NE(error_of("tilt", "{}", hw::make_motion_mind_tilt).find("hardware.tilt.counts_per"),
            std::string::npos);
  EXPECT_NE(error_of("tilt", "{address: 2, counts_per_degree: 200}", hw::make_motion_mind_tilt)
                .find("hardware.tilt.address"),
            std::string::npos);
}

TEST_F(MotionMindFactoryTest, TheTiltWithoutAMotionMindBaseNeedsADevice) {
  assembly_.laser_source = &laser_;
  EXPECT_NE(error_of("tilt", "{counts_per_degree: 200}", hw::make_motion_mind_tilt)
                .find("hardware.tilt.device"),
            std::string::npos);
}

}  // namespace
}  // namespace mobot::emulate
