// The SICK LMS2xx driver against the emulated LMS on a pseudo-terminal: the real serial code, the
// real start-up sequence (9600 baud, the switch to the streaming rate, the variant, continuous
// output), the scans it streams, and each fault the line can have.
#include "drivers/hardware/sick_lms2xx_laser.h"

#include <gtest/gtest.h>

#include <cmath>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <thread>
#include <vector>

#include "drivers/hardware/sick_lms2xx_devices.h"
#include "drivers/sim/robot_profile.h"
#include "tests/unit/emulate/line_harness.h"
#include "tools/emulate/devices/sick_lms2xx_device.h"

namespace mobot::emulate {
namespace {

namespace sick = protocol::sick;
using drivers::hardware::SickLms2xxLaser;
using drivers::hardware::SickLms2xxLaserOptions;
using testing::eventually;
using Clock = std::chrono::steady_clock;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kWallX_m = 3.0;
constexpr double kMountX_m = 0.2;

// A wall across the whole map at x = 3 m, as tall as anything.
class WallWorld final : public EmulatedWorld {
 public:
  geometry::Pose2D base_pose() const override { return pose_; }
  void set_base_pose(const geometry::Pose2D& pose) override { pose_ = pose; }
  std::optional<double> cast_ray(geometry::Point2D from, double angle_rad, double /*height_m*/,
                                 double max_range_m) const override {
    const double c = std::cos(angle_rad);
    if (c <= 0.0) return std::nullopt;
    const double range_m = (kWallX_m - from.x) / c;
    if (range_m < 0.0 || range_m > max_range_m) return std::nullopt;
    return range_m;
  }

 private:
  geometry::Pose2D pose_;
};

// The emulated LMS behind a line that can tamper with the host's variant request: rewritten to
// 180 deg at 0.25 deg (which the LMS refuses), or with its CRC spoilt (which the LMS NAKs).
class TamperingLine final : public EmulatedDevice {
 public:
  enum class Tamper { kNone, kRefuseVariant, kDamageVariant };

  explicit TamperingLine(std::unique_ptr<SickLms2xxDevice> lms) : lms_(std::move(lms)) {}

  void set_tamper(Tamper tamper) { tamper_ = tamper; }

  std::string_view name() const override { return lms_->name(); }
  void receive(std::span<const std::uint8_t> bytes, double now_s) override {
    for (const sick::StreamEvent& event : requests_.feed(bytes)) {
      if (event.kind != sick::StreamEvent::Kind::kTelegram) continue;
      const bool variant = event.telegram.command() == sick::kVariantCommand;
      std::vector<std::uint8_t> wire =
          variant && tamper_ == Tamper::kRefuseVariant
              ? sick::variant_request(
                    {sick::ScanAngle::k180Deg, sick::AngularResolution::kQuarterDeg})
              : sick::encode_telegram(event.telegram.address, event.telegram.payload);
      if (variant && tamper_ == Tamper::kDamageVariant) wire.back() ^= 0xFFU;
      lms_->receive(wire, now_s);
    }
  }
  std::vector<std::uint8_t> transmit(double now_s) override { return lms_->transmit(now_s); }
  void set_bad_checksums(bool on) override { lms_->set_bad_checksums(on); }

 private:
  std::unique_ptr<SickLms2xxDevice> lms_;
  sick::TelegramStream requests_{sick::StreamDirection::kToLms};
  Tamper tamper_ = Tamper::kNone;
};

struct LineSetup {
  unsigned baud = 38400;
  sick::AngularResolution resolution = sick::AngularResolution::kHalfDeg;
  SickLms2xxDevice::Options lms = exact_lms();
  bool tampering = false;

  static SickLms2xxDevice::Options exact_lms() {
    SickLms2xxDevice::Options options;
    options.range_sigma_m = 0.0;
    return options;
  }
};

class SickLms2xxLaserTest : public ::testing::Test {
 protected:
  ~SickLms2xxLaserTest() override {
    laser_.reset();
    harness_.reset();
  }

  void start(const LineSetup& setup = {}) {
    auto lms = std::make_unique<SickLms2xxDevice>(world_, setup.lms);
    model_ = lms.get();
    std::unique_ptr<EmulatedDevice> device;
    if (setup.tampering) {
      auto tampering = std::make_unique<TamperingLine>(std::move(lms));
      tampering_ = tampering.get();
      device = std::move(tampering);
    } else {
      device = std::move(lms);
    }
    harness_ = std::make_unique<testing::LineHarness>(std::move(device));
    SickLms2xxLaserOptions options;
    options.serial.device = harness_->path().string();
    options.serial.baud = setup.baud;
    options.resolution = setup.resolution;
    options.sensor_in_base = {kMountX_m, 0.0, 0.0};
    laser_ = std::make_unique<SickLms2xxLaser>(options);
    laser_->add_listener([this](const msgs::LaserScan& scan, Clock::time_point at) {
      const std::lock_guard lock(mutex_);
      heard_.push_back(at);
      last_heard_ = scan;
    });
    laser_->start();
  }

  bool ok() const { return laser_->status().ok; }
  std::string reason() const { return laser_->status().reason; }

  // The emulated LMS's state, read between two steps of its line.
  struct LmsState {
    int baud = 0;
    sick::OperatingMode mode = sick::OperatingMode::kOnRequest;
    sick::Variant variant;
  };
  LmsState lms_state() {
    LmsState state;
    harness_->with_line([&](DeviceLine&) {
      state = {model_->requested_baud(), model_->operating_mode(), model_->variant()};
    });
    return state;
  }

  void fault(LineFault fault) {
    harness_->with_line([&](DeviceLine& line) { line.set_fault(fault, harness_->seconds(), 0); });
  }
  void clear_fault() {
    harness_->with_line([&](DeviceLine& line) { line.clear_fault(); });
  }

  // Scans per second the listener heard over `window_s`.
  double measured_rate_hz(double window_s) {
    {
      const std::lock_guard lock(mutex_);
      heard_.clear();
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(window_s));
    const std::lock_guard lock(mutex_);
    if (heard_.size() < 2) return 0.0;
    return static_cast<double>(heard_.size() - 1) /
           std::chrono::duration<double>(heard_.back() - heard_.front()).count();
  }

  // A scan of the wall: its geometry, and the range of every beam that sees the wall squarely.
  static void expect_wall(const msgs::LaserScan& scan, std::size_t beams, double increment_deg) {
    ASSERT_EQ(scan.ranges_m.size(), beams);
    EXPECT_NEAR(scan.angle_min_rad, -std::numbers::pi / 2.0, 1e-6);
    EXPECT_NEAR(scan.angle_increment_rad, increment_deg * kDeg, 1e-7);
    EXPECT_EQ(scan.sensor_in_base, (geometry::Pose2D{kMountX_m, 0.0, 0.0}));
    EXPECT_FLOAT_EQ(scan.range_min_m, 0.4F);
    EXPECT_FLOAT_EQ(scan.range_max_m, 80.0F);
    int checked = 0;
    for (std::size_t i = 0; i < beams; ++i) {
      const double beam_rad =
          scan.angle_min_rad + static_cast<double>(i) * scan.angle_increment_rad;
      if (std::abs(beam_rad) > 70.0 * kDeg) continue;
      // Centimetre codes: half a centimetre off at most.
      EXPECT_NEAR(scan.ranges_m[i], (kWallX_m - kMountX_m) / std::cos(beam_rad), 0.006) << i;
      ++checked;
    }
    EXPECT_GT(checked, static_cast<int>(beams) / 2);
    // Along the wall nothing is in range: "no return", beyond range_max_m.
    EXPECT_GT(scan.ranges_m.front(), scan.range_max_m);
    EXPECT_GT(scan.ranges_m.back(), scan.range_max_m);
  }

  WallWorld world_;
  SickLms2xxDevice* model_ = nullptr;
  TamperingLine* tampering_ = nullptr;
  std::unique_ptr<testing::LineHarness> harness_;
  std::unique_ptr<SickLms2xxLaser> laser_;
  std::mutex mutex_;
  std::vector<Clock::time_point> heard_;
  std::optional<msgs::LaserScan> last_heard_;
};

TEST(SickLms2xxScanRate, FollowsTheBaudRateAndTheResolution) {
  using drivers::hardware::sick_lms2xx_scan_rate_hz;
  using sick::AngularResolution;
  EXPECT_DOUBLE_EQ(sick_lms2xx_scan_rate_hz(38400, AngularResolution::kOneDeg), 75.0 / 8.0);
  EXPECT_DOUBLE_EQ(sick_lms2xx_scan_rate_hz(38400, AngularResolution::kHalfDeg), 75.0 / 16.0);
  EXPECT_DOUBLE_EQ(sick_lms2xx_scan_rate_hz(500000, AngularResolution::kOneDeg), 75.0);
  EXPECT_DOUBLE_EQ(sick_lms2xx_scan_rate_hz(500000, AngularResolution::kHalfDeg), 37.5);
  EXPECT_DOUBLE_EQ(sick_lms2xx_scan_rate_hz(500000, AngularResolution::kQuarterDeg), 18.75);
}

TEST(SickLms2xxLaserOptions, RefusesWhatTheLmsCannotStream) {
  SickLms2xxLaserOptions options;
  options.serial.device = "/nonexistent";
  options.serial.baud = 9600;
  EXPECT_THROW(SickLms2xxLaser{options}, std::invalid_argument);
  options.serial.baud = 38400;
  options.resolution = sick::AngularResolution::kQuarterDeg;
  EXPECT_THROW(SickLms2xxLaser{options}, std::invalid_argument);
  options.serial.baud = 500000;
  EXPECT_NO_THROW(SickLms2xxLaser{options});
}

TEST_F(SickLms2xxLaserTest, SwitchesFrom9600AndStreamsHalfDegreeScansOfTheWallAt38400) {
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
  const LmsState state = lms_state();
  EXPECT_EQ(state.baud, 38400);
  EXPECT_EQ(state.mode, sick::OperatingMode::kContinuousAllValues);
  EXPECT_EQ(state.variant,
            (sick::Variant{sick::ScanAngle::k180Deg, sick::AngularResolution::kHalfDeg}));

  const double rate_hz = measured_rate_hz(3.0);
  EXPECT_NEAR(rate_hz, laser_->scan_rate_hz(), 0.1 * laser_->scan_rate_hz());
  std::optional<msgs::LaserScan> scan;
  ASSERT_TRUE(eventually([&] { return (scan = laser_->take_scan()).has_value(); }, 1.0));
  expect_wall(*scan, 361, 0.5);
  EXPECT_EQ(scan->stamp_s, 0.0) << "the poller stamps it with the robot clock";

  const drivers::DeviceCounters counters = laser_->health().counters();
  EXPECT_EQ(counters.name, "laser");
  EXPECT_GT(counters.bytes, 10U * 732U);
  EXPECT_GE(counters.frames, 10U);
  EXPECT_EQ(counters.checksum_errors, 0U);
  EXPECT_EQ(counters.reconnects, 0U);
  std::printf("38400 baud, 0.5 deg: %.2f Hz (expected %.2f)\n", rate_hz, laser_->scan_rate_hz());
}

TEST_F(SickLms2xxLaserTest, StreamsOneDegreeScansAtNineHertzAt38400) {
  start({.resolution = sick::AngularResolution::kOneDeg});
  ASSERT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
  const double rate_hz = measured_rate_hz(3.0);
  EXPECT_NEAR(rate_hz, 9.375, 0.1 * 9.375);
  std::optional<msgs::LaserScan> scan;
  ASSERT_TRUE(eventually([&] { return (scan = laser_->take_scan()).has_value(); }, 1.0));
  expect_wall(*scan, 181, 1.0);
  std::printf("38400 baud, 1 deg: %.2f Hz (expected 9.38)\n", rate_hz);
}

struct FastCase {
  sick::AngularResolution resolution;
  std::size_t beams;
  double increment_deg;
  double rate_hz;
  sick::OperatingMode mode;
  sick::Variant variant;
};

class SickLms2xxLaserFastTest : public SickLms2xxLaserTest,
                                public ::testing::WithParamInterface<FastCase> {};

TEST_P(SickLms2xxLaserFastTest, StreamsEveryScanTheMirrorMakesAt500000) {
  const FastCase& c = GetParam();
  start({.baud = 500000, .resolution = c.resolution});
  ASSERT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
  const LmsState state = lms_state();
  EXPECT_EQ(state.baud, 500000);
  EXPECT_EQ(state.mode, c.mode);
  EXPECT_EQ(state.variant, c.variant);
  const double rate_hz = measured_rate_hz(2.0);
  EXPECT_NEAR(rate_hz, c.rate_hz, 0.1 * c.rate_hz);
  EXPECT_DOUBLE_EQ(laser_->scan_rate_hz(), c.rate_hz);
  std::optional<msgs::LaserScan> scan;
  ASSERT_TRUE(eventually([&] { return (scan = laser_->take_scan()).has_value(); }, 1.0));
  expect_wall(*scan, c.beams, c.increment_deg);
  std::printf("500000 baud, %.2f deg: %.2f Hz (expected %.2f)\n", c.increment_deg, rate_hz,
              c.rate_hz);
}

INSTANTIATE_TEST_SUITE_P(
    Resolutions, SickLms2xxLaserFastTest,
    ::testing::Values(FastCase{sick::AngularResolution::kOneDeg,
                               181,
                               1.0,
                               75.0,
                               sick::OperatingMode::kContinuousAllValues,
                               {sick::ScanAngle::k180Deg, sick::AngularResolution::kOneDeg}},
                      FastCase{sick::AngularResolution::kHalfDeg,
                               361,
                               0.5,
                               37.5,
                               sick::OperatingMode::kContinuousAllValues,
                               {sick::ScanAngle::k180Deg, sick::AngularResolution::kHalfDeg}},
                      // Interlaced: the 100 deg / 0.25 deg variant streamed as 180 deg parts.
                      FastCase{sick::AngularResolution::kQuarterDeg,
                               721,
                               0.25,
                               18.75,
                               sick::OperatingMode::kContinuousPartialScans,
                               {sick::ScanAngle::k100Deg, sick::AngularResolution::kQuarterDeg}}));

TEST_F(SickLms2xxLaserTest, TheListenerHearsEveryScanAndTakeScanKeepsTheNewest) {
  start({.baud = 500000, .resolution = sick::AngularResolution::kOneDeg});
  ASSERT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
  ASSERT_TRUE(eventually([&] { return laser_->take_scan().has_value(); }, 1.0));
  const auto asked_at = Clock::now();
  std::size_t heard = 0;
  {
    const std::lock_guard lock(mutex_);
    heard = heard_.size();
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const std::lock_guard lock(mutex_);
  // 15 scans in 200 ms at 75 Hz, each dated before it was heard.
  EXPECT_GE(heard_.size() - heard, 10U);
  EXPECT_LT(heard_.back(), Clock::now());
  EXPECT_GT(heard_.back(), asked_at);
  const std::optional<msgs::LaserScan> newest = laser_->take_scan();
  ASSERT_TRUE(newest.has_value());
  ASSERT_TRUE(last_heard_.has_value());
  EXPECT_EQ(newest->ranges_m, last_heard_->ranges_m);
}

TEST_F(SickLms2xxLaserTest, FindsALaserStreamingAtAnotherRateAndSetsItUp) {
  // Left streaming 1 deg scans at 500000 baud by an earlier run.
  LineSetup setup;
  setup.lms.initial_baud = 500000;
  setup.lms.initial_mode = sick::OperatingMode::kContinuousAllValues;
  setup.lms.initial_variant = {sick::ScanAngle::k180Deg, sick::AngularResolution::kOneDeg};
  start(setup);
  ASSERT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
  const LmsState state = lms_state();
  EXPECT_EQ(state.baud, 38400);
  EXPECT_EQ(state.variant,
            (sick::Variant{sick::ScanAngle::k180Deg, sick::AngularResolution::kHalfDeg}));
  std::optional<msgs::LaserScan> scan;
  ASSERT_TRUE(eventually([&] { return (scan = laser_->take_scan()).has_value(); }, 1.0));
  expect_wall(*scan, 361, 0.5);
}

TEST_F(SickLms2xxLaserTest, StoppingSwitchesTheLaserBackToOnRequest) {
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
  laser_->stop();
  EXPECT_EQ(reason(), "stopped");
  EXPECT_TRUE(eventually([&] { return lms_state().mode == sick::OperatingMode::kOnRequest; }, 1.0));
}

TEST_F(SickLms2xxLaserTest, AMissingDeviceIsMissingUntilItAppears) {
  start();
  fault(LineFault::kUnplug);
  EXPECT_TRUE(eventually([&] { return reason() == "missing"; }, 2.0)) << reason();
  clear_fault();
  EXPECT_TRUE(eventually([&] { return ok(); }, 6.0)) << reason();
}

TEST_F(SickLms2xxLaserTest, EachLineFaultIsReportedAndRecoveredFrom) {
  start();
  ASSERT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
  const std::vector<std::pair<LineFault, std::string>> faults{
      {LineFault::kUnplug, "missing"},  {LineFault::kDrop, "silent"},
      {LineFault::kStall, "silent"},    {LineFault::kChecksum, "checksum"},
      {LineFault::kGarbage, "garbage"},
  };
  for (const auto& [line_fault, expected] : faults) {
    const auto faulted_at = Clock::now();
    fault(line_fault);
    EXPECT_TRUE(eventually([&] { return !ok(); }, 2.0)) << expected;
    const double noticed_s = std::chrono::duration<double>(Clock::now() - faulted_at).count();
    // Noise reads as no scan (silent) or, now and then, as a telegram with a bad CRC.
    if (line_fault != LineFault::kGarbage) {
      EXPECT_EQ(reason(), expected);
    }
    // Held for a while: the reason stays while the fault does, whatever the reopens find.
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    EXPECT_FALSE(ok()) << expected;
    if (line_fault != LineFault::kGarbage) {
      EXPECT_EQ(reason(), expected);
    }
    const std::string held_reason = reason();
    const auto cleared_at = Clock::now();
    clear_fault();
    EXPECT_TRUE(eventually([&] { return ok(); }, 10.0)) << expected << ": " << reason();
    const double recovered_s = std::chrono::duration<double>(Clock::now() - cleared_at).count();
    std::printf("%s: noticed in %.2f s as %s, recovered in %.2f s\n", expected.c_str(), noticed_s,
                held_reason.c_str(), recovered_s);
    ASSERT_TRUE(eventually([&] { return laser_->take_scan().has_value(); }, 1.0)) << expected;
  }
  const drivers::DeviceCounters counters = laser_->health().counters();
  EXPECT_GE(counters.reconnects, 5U);
  EXPECT_GE(counters.checksum_errors, 3U);
}

TEST_F(SickLms2xxLaserTest, ARefusedVariantIsReportedAndRetried) {
  start({.tampering = true});
  ASSERT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
  harness_->with_line(
      [&](DeviceLine&) { tampering_->set_tamper(TamperingLine::Tamper::kRefuseVariant); });
  // The next set-up meets the refusal: unplugging makes one.
  fault(LineFault::kUnplug);
  ASSERT_TRUE(eventually([&] { return !ok(); }, 2.0));
  clear_fault();
  EXPECT_TRUE(eventually([&] { return reason() == "refused"; }, 4.0)) << reason();
  harness_->with_line([&](DeviceLine&) { tampering_->set_tamper(TamperingLine::Tamper::kNone); });
  EXPECT_TRUE(eventually([&] { return ok(); }, 6.0)) << reason();
}

TEST_F(SickLms2xxLaserTest, ARequestTheLaserKeepsNakingIsRefused) {
  LineSetup setup;
  setup.tampering = true;
  start(setup);
  harness_->with_line(
      [&](DeviceLine&) { tampering_->set_tamper(TamperingLine::Tamper::kDamageVariant); });
  EXPECT_TRUE(eventually([&] { return reason() == "refused"; }, 4.0)) << reason();
  harness_->with_line([&](DeviceLine&) { tampering_->set_tamper(TamperingLine::Tamper::kNone); });
  EXPECT_TRUE(eventually([&] { return ok(); }, 6.0)) << reason();
}

TEST_F(SickLms2xxLaserTest, FiftyUnplugsLeakNoFileDescriptor) {
  start({.baud = 500000, .resolution = sick::AngularResolution::kOneDeg});
  ASSERT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
  const int before = testing::open_fd_count();
  for (int i = 0; i < 50; ++i) {
    fault(LineFault::kUnplug);
    ASSERT_TRUE(eventually([&] { return !ok(); }, 1.0)) << i;
    clear_fault();
    ASSERT_TRUE(eventually([&] { return ok(); }, 4.0)) << i << ": " << reason();
  }
  EXPECT_EQ(testing::open_fd_count(), before);
}

// The factory: the config keys, their errors, and what it builds.
class SickLms2xxFactoryTest : public ::testing::Test {
 protected:
  drivers::hardware::HardwareAssembly make(const std::string& yaml) {
    drivers::hardware::HardwareAssembly assembly{profile_, options_, {}, {}, nullptr, {}};
    drivers::hardware::DeviceReader entry(YAML::Load(yaml), "hardware.laser");
    drivers::hardware::make_sick_lms2xx(entry, assembly);
    return assembly;
  }
  std::string error_of(const std::string& yaml) {
    try {
      make(yaml);
    } catch (const drivers::BackendError& error) {
      return error.what();
    }
    return "no error";
  }

  sim::RobotProfile profile_ = sim::r1_profile();
  drivers::BackendOptions options_;
};

TEST_F(SickLms2xxFactoryTest, BuildsTheLaserAtTheProfilesMount) {
  drivers::hardware::HardwareAssembly assembly = make("{device: /dev/ttyS0}");
  ASSERT_NE(assembly.drivers.laser, nullptr);
  EXPECT_EQ(assembly.drivers.laser->name(), "laser");
  EXPECT_DOUBLE_EQ(assembly.drivers.laser->nominal_rate_hz(), 75.0 / 16.0);
  EXPECT_FALSE(assembly.drivers.laser->poll(1.0).has_value());
  ASSERT_NE(assembly.laser_source, nullptr);
  ASSERT_EQ(assembly.devices.size(), 1U);
  ASSERT_EQ(assembly.devices[0]->counters().size(), 1U);
  EXPECT_EQ(assembly.devices[0]->counters()[0].name, "laser");
  const auto* laser = dynamic_cast<SickLms2xxLaser*>(assembly.laser_source);
  ASSERT_NE(laser, nullptr);
  EXPECT_EQ(laser->options().serial.device, "/dev/ttyS0");
  EXPECT_EQ(laser->options().serial.baud, 38400U);
  EXPECT_EQ(laser->options().resolution, sick::AngularResolution::kHalfDeg);
  EXPECT_EQ(laser->options().sensor_in_base, profile_.laser_in_base);
  EXPECT_DOUBLE_EQ(laser->options().range_min_m, profile_.laser_range_min_m);
  EXPECT_DOUBLE_EQ(laser->options().range_max_m, profile_.laser_range_max_m);

  const drivers::hardware::HardwareAssembly quarter =
      make("{device: /dev/ttyUSB0, baud: 500000, resolution_deg: 0.25}");
  EXPECT_DOUBLE_EQ(quarter.drivers.laser->nominal_rate_hz(), 18.75);
  const drivers::hardware::HardwareAssembly fast =
      make("{device: /dev/ttyUSB0, baud: 500000, resolution_deg: 1}");
  EXPECT_DOUBLE_EQ(fast.drivers.laser->nominal_rate_hz(), 75.0);
}

TEST_F(SickLms2xxFactoryTest, NamesTheKeyOfEveryBadOption) {
  EXPECT_NE(error_of("{baud: 38400}").find("hardware.laser.device"), std::string::npos);
  EXPECT_NE(error_of("{device: /dev/ttyS0, baud: 9600}").find("hardware.laser.baud"),
            std::string::npos);
  EXPECT_NE(error_of("{device: /dev/ttyS0, baud: fast}").find("hardware.laser.baud"),
            std::string::npos);
  EXPECT_NE(
      error_of("{device: /dev/ttyS0, resolution_deg: 0.3}").find("hardware.laser.resolution_deg"),
      std::string::npos);
  EXPECT_NE(
      error_of("{device: /dev/ttyS0, resolution_deg: 2}").find("hardware.laser.resolution_deg"),
      std::string::npos);
  const std::string quarter = error_of("{device: /dev/ttyS0, resolution_deg: 0.25}");
  EXPECT_NE(quarter.find("hardware.laser.resolution_deg"), std::string::npos) << quarter;
  EXPECT_NE(quarter.find("500000"), std::string::npos) << quarter;
  EXPECT_NE(error_of("{device: /dev/ttyS0, rate_hz: 10}").find("hardware.laser.rate_hz"),
            std::string::npos);
}

}  // namespace
}  // namespace mobot::emulate
