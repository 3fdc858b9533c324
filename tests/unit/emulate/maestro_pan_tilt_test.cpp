// The camera head's Maestro driver against the emulated Maestro on a pseudo-terminal: the real
// serial code, the real protocol, each fault the line can have; and its factory, as the hardware
// backend calls it.
#include "drivers/hardware/maestro_pan_tilt.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <thread>

#include "drivers/hardware/camera_devices.h"
#include "drivers/hardware/hardware_backend.h"
#include "drivers/hardware/maestro_devices.h"
#include "drivers/sim/robot_profile.h"
#include "tests/unit/emulate/line_harness.h"
#include "tools/emulate/devices/maestro_device.h"

namespace mobot::emulate {
namespace {

namespace hw = drivers::hardware;
namespace mx = protocol::maestro;
using testing::eventually;

constexpr double kRadPerDeg = std::numbers::pi / 180.0;
// One quarter-microsecond of a servo at 1000 us per 90 deg.
constexpr double kQuarterUsRad = 1.0 / (4.0 * 2000.0 / std::numbers::pi);

class MaestroPanTiltTest : public ::testing::Test {
 protected:
  ~MaestroPanTiltTest() override {
    if (head_) head_->stop();
    head_.reset();
    harness_.reset();
  }

  void make_line(MaestroDeviceOptions options = {}) { make_line(options, world_); }
  void make_line(MaestroDeviceOptions options, const EmulatedWorld& world) {
    auto device = std::make_unique<MaestroDevice>(options, world);
    model_ = device.get();
    harness_ = std::make_unique<testing::LineHarness>(std::move(device));
  }

  hw::MaestroPanTiltOptions driver_options() const {
    hw::MaestroPanTiltOptions options;
    options.serial.device = harness_->path().string();
    options.head.min_pan_rad = -90.0 * kRadPerDeg;
    options.head.max_pan_rad = 90.0 * kRadPerDeg;
    options.head.max_pan_rate_rad_s = 1.0;
    return options;
  }

  void start(const hw::MaestroPanTiltOptions& options) {
    head_ = std::make_unique<hw::MaestroPanTilt>(options);
    head_->start();
  }
  void start() { start(driver_options()); }

  bool ok() const { return head_->status().ok; }
  // Answering, and the positions read at least once (before that, current() is the target).
  bool polling() const { return ok() && head_->polls() > 0; }
  std::string reason() const { return head_->status().reason; }

  template <class T>
  T on_model(const std::function<T(const MaestroDevice&)>& read) {
    T value{};
    harness_->with_line([&](DeviceLine&) { value = read(*model_); });
    return value;
  }
  std::uint16_t servo_target(int channel) {
    return on_model<std::uint16_t>(
        [channel](const MaestroDevice& maestro) { return maestro.target_qus(channel); });
  }
  std::optional<double> emulated_pan_rad() {
    return on_model<std::optional<double>>([](const MaestroDevice& m) { return m.pan_rad(); });
  }
  std::optional<double> emulated_range_m() {
    return on_model<std::optional<double>>(
        [](const MaestroDevice& m) { return m.ranger_range_m(); });
  }
  void with_model(const std::function<void(MaestroDevice&)>& action) {
    harness_->with_line([&](DeviceLine&) { action(*model_); });
  }
  void set_fault(LineFault fault) {
    harness_->with_line([&](DeviceLine& line) { line.set_fault(fault, harness_->seconds(), 0.0); });
  }
  void clear_fault() {
    harness_->with_line([](DeviceLine& line) { line.clear_fault(); });
  }
  // The newest range reading, waiting up to a second for one.
  std::optional<msgs::HeadRange> next_range() {
    std::optional<msgs::HeadRange> range;
    eventually([&] { return (range = head_->take_range()).has_value(); }, 1.0);
    return range;
  }

  // A 4 x 4 m room, the base at its centre facing +x; or nothing at all.
  testing::BoxWorld world_{-2.0, 2.0, -2.0, 2.0};
  testing::EmptyWorld empty_world_;
  MaestroDevice* model_ = nullptr;
  std::unique_ptr<testing::LineHarness> harness_;
  std::unique_ptr<hw::MaestroPanTilt> head_;
};

TEST_F(MaestroPanTiltTest, TargetsReachTheServosAndCurrentFollowsTheSlew) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return polling(); }, 2.0)) << reason();
  // Looking ahead: the first pulse after power-up, which the Maestro jumps to.
  EXPECT_TRUE(eventually([&] { return servo_target(0) == 6000 && servo_target(1) == 6000; }, 1.0));
  EXPECT_TRUE(eventually([&] { return std::abs(head_->current().pan_rad) < 1e-9; }, 1.0));

  // 1 rad/s is the Maestro's speed 25 (0.982 rad/s): 1 rad takes about a second.
  head_->set_target({1.0, 0.5});
  EXPECT_EQ(head_->target(), (vision::PanTilt{1.0, 0.5}));
  EXPECT_TRUE(eventually([&] { return servo_target(0) == mx::target_for_angle({}, 1.0); }, 0.5));
  // (seconds since the target, pan) as the control loop would read them.
  std::vector<std::pair<double, double>> pans;
  const auto started = std::chrono::steady_clock::now();
  const auto since_s = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  };
  while (since_s() < 1.5) {
    pans.emplace_back(since_s(), head_->current().pan_rad);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  // It moved through the angles in between, never back, at about the speed limit.
  bool monotonic = true;
  for (std::size_t i = 1; i < pans.size(); ++i) {
    monotonic = monotonic && pans[i].second >= pans[i - 1].second;
  }
  EXPECT_TRUE(monotonic);
  const auto first =
      std::find_if(pans.begin(), pans.end(), [](const auto& p) { return p.second > 0.2; });
  const auto last =
      std::find_if(pans.begin(), pans.end(), [](const auto& p) { return p.second > 0.8; });
  ASSERT_TRUE(first != pans.end() && last != pans.end() && last->first > first->first);
  EXPECT_NEAR((last->second - first->second) / (last->first - first->first),
              mx::rate_for_speed({}, 25), 0.15);
  EXPECT_TRUE(eventually(
      [&] { return std::abs(head_->current().pan_rad - 1.0) < 2.0 * kQuarterUsRad; }, 2.0))
      << head_->current().pan_rad;
  EXPECT_NEAR(head_->current().tilt_rad, 0.5, 2.0 * kQuarterUsRad);
  // current() is what the Maestro reports.
  EXPECT_NEAR(*emulated_pan_rad(), head_->current().pan_rad, 1e-9);
  EXPECT_GT(head_->polls(), 40U);
  EXPECT_EQ(head_->counters().name, "pan_tilt");
  EXPECT_GT(head_->counters().frames, 40U);
}

TEST_F(MaestroPanTiltTest, SetTargetClampsHoldsNaNAndNeverBlocks) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return polling(); }, 2.0)) << reason();
  head_->set_target({5.0, -2.0});
  EXPECT_NEAR(head_->target().pan_rad, 90.0 * kRadPerDeg, 1e-12);
  EXPECT_NEAR(head_->target().tilt_rad, -30.0 * kRadPerDeg, 1e-12);
  head_->set_target({std::numeric_limits<double>::quiet_NaN(), 0.2});
  EXPECT_NEAR(head_->target().pan_rad, 90.0 * kRadPerDeg, 1e-12);
  EXPECT_DOUBLE_EQ(head_->target().tilt_rad, 0.2);
  // A hung Maestro does not hold up the control loop.
  set_fault(LineFault::kStall);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const auto before = std::chrono::steady_clock::now();
  for (int i = 0; i < 1000; ++i) head_->set_target({0.001 * i, 0.0});
  EXPECT_LT(std::chrono::steady_clock::now() - before, std::chrono::milliseconds(20));
  clear_fault();
}

TEST_F(MaestroPanTiltTest, TheRangeReadsTheEmulatedWall) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return polling(); }, 2.0)) << reason();
  ASSERT_TRUE(eventually([&] { return emulated_range_m().has_value(); }, 1.0));
  // The ranger samples every 49 ms: a reading that old may still be out.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  head_->take_range();
  std::optional<msgs::HeadRange> range = next_range();
  ASSERT_TRUE(range);
  ASSERT_TRUE(range->range_m);
  // The wall 2 m ahead of the base, less the lens's 5 cm: whole inches, then 5 mV steps.
  EXPECT_NEAR(*range->range_m, *emulated_range_m(), 0.03);
  EXPECT_NEAR(*range->range_m, 1.95, 0.03);
  EXPECT_DOUBLE_EQ(range->range_max_m, 6.0);

  // Turned to the left wall, 0.5 m nearer.
  harness_->with_line([&](DeviceLine&) { world_.set_base_pose({0.0, 0.5, 0.0}); });
  head_->set_target({90.0 * kRadPerDeg, 0.0});
  ASSERT_TRUE(eventually(
      [&] { return std::abs(head_->current().pan_rad - std::numbers::pi / 2) < 1e-3; }, 3.0));
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  head_->take_range();
  range = next_range();
  ASSERT_TRUE(range && range->range_m);
  EXPECT_NEAR(*range->range_m, 1.45, 0.03);
}

TEST_F(MaestroPanTiltTest, NothingWithinRangeIsNoRange) {
  make_line({}, empty_world_);
  start();
  ASSERT_TRUE(eventually([&] { return polling(); }, 2.0)) << reason();
  const std::optional<msgs::HeadRange> range = next_range();
  ASSERT_TRUE(range);
  EXPECT_FALSE(range->range_m);
}

TEST_F(MaestroPanTiltTest, EachLineFaultIsReportedAndRecoveredFrom) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return polling(); }, 2.0)) << reason();
  const std::vector<std::pair<LineFault, std::string>> faults{
      {LineFault::kUnplug, "missing"},
      {LineFault::kDrop, "silent"},
      {LineFault::kStall, "silent"},
      {LineFault::kGarbage, "garbage"},
      // The Maestro's answers carry no checksum: garbled, they are garbage.
      {LineFault::kChecksum, "garbage"},
  };
  double pan_rad = 0.2;
  for (const auto& [fault, expected] : faults) {
    SCOPED_TRACE(expected);
    set_fault(fault);
    EXPECT_TRUE(eventually([&] { return !ok(); }, 1.0));
    EXPECT_EQ(reason(), expected);
    // Not one reading from a line that is down.
    head_->take_range();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    EXPECT_FALSE(head_->take_range());
    clear_fault();
    EXPECT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
    // The head follows again.
    head_->set_target({pan_rad, 0.0});
    EXPECT_TRUE(
        eventually([&] { return std::abs(head_->current().pan_rad - pan_rad) < 1e-3; }, 3.0))
        << head_->current().pan_rad;
    EXPECT_TRUE(next_range());
    pan_rad = -pan_rad * 1.5;
  }
  EXPECT_GE(head_->health().reconnects(), 5U);
  EXPECT_GE(head_->health().checksum_errors(), 6U);
}

TEST_F(MaestroPanTiltTest, ErrorsAreReadAndTheServosPutBack) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return polling(); }, 2.0)) << reason();
  head_->set_target({0.3, 0.0});
  ASSERT_TRUE(eventually([&] { return std::abs(head_->current().pan_rad - 0.3) < 1e-3; }, 2.0));
  ASSERT_TRUE(eventually(
      [&] { return emulated_pan_rad() && std::abs(*emulated_pan_rad() - 0.3) < 1e-3; }, 1.0));
  // An error sends the servos home (off); the next cycle's targets put them back.
  with_model([](MaestroDevice& maestro) { maestro.raise_errors(mx::error_bit::kSerialOverrun); });
  EXPECT_TRUE(
      eventually([&] { return head_->last_errors() == mx::error_bit::kSerialOverrun; }, 1.0));
  EXPECT_TRUE(eventually(
      [&] { return emulated_pan_rad() && std::abs(*emulated_pan_rad() - 0.3) < 1e-3; }, 1.0));
  // One error is no fault (a loaded machine may still miss a poll: not the point here).
  EXPECT_NE(reason(), "refused");
  // The driver's reading is up to a poll behind the servo.
  EXPECT_TRUE(eventually([&] { return std::abs(head_->current().pan_rad - 0.3) < 1e-3; }, 1.0))
      << head_->current().pan_rad;
}

TEST_F(MaestroPanTiltTest, ErrorsThatKeepComingRefuseTheDeviceUntilTheyStop) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return polling(); }, 2.0)) << reason();
  with_model(
      [](MaestroDevice& maestro) { maestro.keep_raising_errors(mx::error_bit::kSerialTimeout); });
  EXPECT_TRUE(eventually([&] { return reason() == "refused"; }, 1.0)) << reason();
  with_model([](MaestroDevice& maestro) { maestro.keep_raising_errors(0); });
  EXPECT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
}

TEST_F(MaestroPanTiltTest, WithCrcBothSidesMustAgree) {
  MaestroDeviceOptions crc_maestro;
  crc_maestro.crc = true;
  make_line(crc_maestro);
  hw::MaestroPanTiltOptions options = driver_options();
  options.crc = true;
  start(options);
  ASSERT_TRUE(eventually([&] { return polling(); }, 2.0)) << reason();
  head_->set_target({-0.4, 0.1});
  EXPECT_TRUE(eventually([&] { return std::abs(head_->current().pan_rad + 0.4) < 1e-3; }, 2.0));
  head_->stop();
  // Commands without their CRC byte are never whole to a Maestro that wants one.
  start(driver_options());
  EXPECT_TRUE(eventually([&] { return reason() == "silent"; }, 2.0)) << reason();
}

TEST_F(MaestroPanTiltTest, AMissingDeviceIsMissingUntilItAppears) {
  make_line();
  set_fault(LineFault::kUnplug);
  start();
  EXPECT_TRUE(eventually([&] { return reason() == "missing"; }, 1.0)) << reason();
  clear_fault();
  EXPECT_TRUE(eventually([&] { return ok(); }, 4.0)) << reason();
  head_->stop();
  EXPECT_EQ(reason(), "stopped");
}

TEST_F(MaestroPanTiltTest, FiftyUnplugsLeakNoFileDescriptor) {
  make_line();
  start();
  ASSERT_TRUE(eventually([&] { return polling(); }, 2.0)) << reason();
  const int before = testing::open_fd_count();
  for (int i = 0; i < 50; ++i) {
    set_fault(LineFault::kUnplug);
    ASSERT_TRUE(eventually([&] { return !ok(); }, 1.0));
    clear_fault();
    ASSERT_TRUE(eventually([&] { return ok(); }, 4.0)) << i << ": " << reason();
  }
  EXPECT_EQ(testing::open_fd_count(), before);
}

TEST(MaestroPanTiltOptions, BadOptionsNameTheirKey) {
  const auto error_of = [](const std::function<void(hw::MaestroPanTiltOptions&)>& spoil) {
    hw::MaestroPanTiltOptions options;
    options.serial.device = "/dev/null";
    spoil(options);
    try {
      hw::MaestroPanTilt head(options);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_of([](auto&) {}), "");
  EXPECT_EQ(error_of([](auto& o) { o.tilt.channel = 0; }), "tilt_channel: channel 0 is the pan's");
  EXPECT_EQ(error_of([](auto& o) { o.pan.channel = 24; }),
            "pan_channel: 24 is not a channel of 0..23");
  EXPECT_EQ(error_of([](auto& o) { o.range_channel = 12; }),
            "range_channel: 12 is not a channel of 0..11");
  EXPECT_EQ(error_of([](auto& o) { o.range_channel = 1; }),
            "range_channel: channel 1 drives a servo");
  EXPECT_EQ(error_of([](auto& o) { o.pan.calibration.sign = 0; }), "pan_sign: 1 or -1");
  EXPECT_EQ(error_of([](auto& o) { o.tilt.calibration.centre_us = 3800.0; }),
            "tilt_max_deg: 45 deg needs a 4300 us pulse, beyond the Maestro's 64..4080 us");
  EXPECT_EQ(error_of([](auto& o) { o.head.max_tilt_rate_rad_s = 0.0; }).rfind("head: ", 0), 0U);
  EXPECT_EQ(error_of([](auto& o) { o.rate_hz = 0.0; }), "rate_hz: must be positive");
}

// The factory, as the hardware backend calls it.
class MaestroFactoryTest : public ::testing::Test {
 protected:
  void make(const char* role, const std::string& yaml,
            void (*factory)(hw::DeviceReader&, hw::HardwareAssembly&)) {
    hw::DeviceReader entry(YAML::Load(yaml), std::string("hardware.") + role);
    factory(entry, assembly_);
  }
  void make_camera(const std::string& size = "width: 640, height: 480") {
    make("camera", "{source: /nonexistent/frame_%03d.png, rate_hz: 15, " + size + "}",
         hw::make_opencv_camera);
  }
  std::string error_of(const std::string& yaml) {
    try {
      make("pan_tilt", yaml, hw::make_pololu_maestro);
    } catch (const drivers::BackendError& error) {
      return error.what();
    }
    return "";
  }

  sim::RobotProfile profile_ = sim::camera_robot_profile();
  drivers::BackendOptions options_;
  hw::HardwareAssembly assembly_{profile_, options_, {}, {}, nullptr, {}};
};

TEST_F(MaestroFactoryTest, MakesThePanTiltCameraAndItsRanger) {
  make_camera();
  make("pan_tilt", "{device: /dev/ttyACM0, tilt_min_deg: -20, range_cone_deg: 20}",
       hw::make_pololu_maestro);
  ASSERT_TRUE(assembly_.drivers.pan_tilt);
  const vision::PanTiltHeadOptions& head = assembly_.drivers.pan_tilt->head();
  EXPECT_NEAR(head.min_pan_rad, -90.0 * kRadPerDeg, 1e-12);
  EXPECT_NEAR(head.max_pan_rad, 90.0 * kRadPerDeg, 1e-12);
  EXPECT_NEAR(head.min_tilt_rad, -20.0 * kRadPerDeg, 1e-12);
  EXPECT_NEAR(head.max_tilt_rad, 45.0 * kRadPerDeg, 1e-12);
  // The profile's head: its column and rates.
  EXPECT_DOUBLE_EQ(head.l0_m, 0.45);
  EXPECT_DOUBLE_EQ(head.mount_x_m, 0.05);
  EXPECT_DOUBLE_EQ(head.max_pan_rate_rad_s, 2.0);
  ASSERT_TRUE(assembly_.drivers.head_range);
  EXPECT_EQ(assembly_.drivers.head_range->name(), "head_range");
  EXPECT_DOUBLE_EQ(assembly_.drivers.head_range->nominal_rate_hz(), 50.0);
  // The camera the head turns.
  ASSERT_TRUE(assembly_.drivers.camera_info);
  const drivers::CameraInfo& camera = *assembly_.drivers.camera_info;
  EXPECT_EQ(camera.kind, "pan_tilt");
  EXPECT_EQ(camera.pinhole.width_px, 640);
  EXPECT_NEAR(camera.range_cone_rad, 20.0 * kRadPerDeg, 1e-12);
  EXPECT_NEAR(camera.height_m, vision::PanTiltHead(head).lens_in_base({}).z_m, 1e-12);
  ASSERT_EQ(assembly_.devices.size(), 2U);
  EXPECT_EQ(assembly_.devices[1]->counters()[0].name, "pan_tilt");
  auto* maestro = dynamic_cast<hw::MaestroPanTilt*>(assembly_.drivers.pan_tilt.get());
  ASSERT_NE(maestro, nullptr);
  EXPECT_EQ(maestro->options().serial.baud, 115200U);
  EXPECT_EQ(maestro->options().range_channel, 2);
  EXPECT_FALSE(maestro->options().crc);
}

TEST_F(MaestroFactoryTest, AHeadWithoutARanger) {
  make_camera();
  make("pan_tilt",
       "{device: /dev/ttyACM0, range_channel: -1, pan_channel: 3, tilt_channel: 4, crc: true, "
       "pan_sign: -1, pan_centre_us: 1480, pan_us_per_rad: 600, pan_speed_dps: 30}",
       hw::make_pololu_maestro);
  EXPECT_FALSE(assembly_.drivers.head_range);
  EXPECT_DOUBLE_EQ(assembly_.drivers.camera_info->range_cone_rad, 0.0);
  auto* maestro = dynamic_cast<hw::MaestroPanTilt*>(assembly_.drivers.pan_tilt.get());
  ASSERT_NE(maestro, nullptr);
  EXPECT_FALSE(maestro->options().range_channel);
  EXPECT_EQ(maestro->options().pan.channel, 3);
  EXPECT_EQ(maestro->options().pan.calibration.sign, -1);
  EXPECT_DOUBLE_EQ(maestro->options().pan.calibration.centre_us, 1480.0);
  EXPECT_NEAR(maestro->head().max_pan_rate_rad_s, 30.0 * kRadPerDeg, 1e-12);
  EXPECT_TRUE(maestro->options().crc);
}

TEST_F(MaestroFactoryTest, BadValuesNameTheKey) {
  EXPECT_EQ(error_of("{device: /dev/ttyACM0}"),
            "hardware.pan_tilt: the head turns the robot's camera; configure hardware.camera as "
            "well");
  make_camera("width: 0");
  EXPECT_NE(error_of("{device: /dev/ttyACM0}").find("give hardware.camera its width and height"),
            std::string::npos);
  make_camera();
  const std::vector<std::pair<std::string, std::string>> cases{
      {"{}", "hardware.pan_tilt.device: the device's path is required"},
      {"{device: d, pan_channel: 24}", "hardware.pan_tilt.pan_channel: 24 is outside the allowed"},
      {"{device: d, tilt_channel: 0}", "hardware.pan_tilt.tilt_channel: channel 0 is the pan's"},
      {"{device: d, range_channel: 1}",
       "hardware.pan_tilt.range_channel: channel 1 drives a servo"},
      {"{device: d, range_channel: 12}", "hardware.pan_tilt.range_channel: 12 is outside"},
      {"{device: d, pan_sign: 0}", "hardware.pan_tilt.pan_sign: 1, or -1"},
      {"{device: d, tilt_sign: 2}", "hardware.pan_tilt.tilt_sign: 2 is outside"},
      {"{device: d, pan_min_deg: 10, pan_max_deg: 10}",
       "hardware.pan_tilt.pan_max_deg: must be above pan_min_deg"},
      {"{device: d, pan_max_deg: 200}", "hardware.pan_tilt.pan_max_deg: 200 is outside"},
      {"{device: d, pan_us_per_rad: 2000}", "hardware.pan_tilt.pan_min_deg: -90 deg needs a"},
      {"{device: d, pan_centre_us: 50}", "hardware.pan_tilt.pan_centre_us: 50 is outside"},
      {"{device: d, tilt_speed_dps: 0}", "hardware.pan_tilt.tilt_speed_dps: 0 is outside"},
      {"{device: d, pan_accel_dps2: -1}", "hardware.pan_tilt.pan_accel_dps2: -1 is outside"},
      {"{device: d, l0_m: x}", "hardware.pan_tilt.l0_m: expected a number"},
      {"{device: d, range_max_m: 0}", "hardware.pan_tilt.range_max_m: 0 is outside"},
      {"{device: d, rate_hz: 500}", "hardware.pan_tilt.rate_hz: 500 is outside"},
      {"{device: d, crc: maybe}", "hardware.pan_tilt.crc: expected true or false"},
      {"{device: d, pan_chanel: 1}", "hardware.pan_tilt.pan_chanel: unknown key"},
  };
  for (const auto& [yaml, message] : cases) {
    EXPECT_EQ(error_of(yaml).rfind(message, 0), 0U) << yaml << " -> " << error_of(yaml);
  }
  EXPECT_FALSE(assembly_.drivers.pan_tilt);
}

TEST(MaestroHardwareBackend, ThePanTiltRoleIsMadeAfterTheCameraItTurns) {
  drivers::BackendOptions options;
  options.backend = "hardware";
  options.profile = "camera_robot";
  // In the file's order the head comes first; the backend makes the camera before it.
  options.hardware = YAML::Load(
      "{pan_tilt: {driver: pololu_maestro, device: /nonexistent/ttyACM0}, "
      "base: {driver: dashgo_arduino, device: /nonexistent/ttyUSB0}, "
      "camera: {driver: opencv, source: /nonexistent/frame_%03d.png, width: 320, height: 240}}");
  const std::unique_ptr<drivers::Backend> backend = hw::make_hardware_backend(options);
  drivers::DriverSet& drivers = backend->drivers();
  ASSERT_TRUE(drivers.pan_tilt);
  ASSERT_TRUE(drivers.head_range);
  EXPECT_EQ(drivers.camera_info->kind, "pan_tilt");
  // Nothing there yet: the head says so, and keeps looking.
  EXPECT_TRUE(eventually([&] { return drivers.pan_tilt->status().reason == "missing"; }, 2.0));
  EXPECT_FALSE(drivers.head_range->status().ok);
  bool listed = false;
  for (const drivers::DeviceCounters& device : backend->device_counters()) {
    listed = listed || device.name == "pan_tilt";
  }
  EXPECT_TRUE(listed);
}

}  // namespace
}  // namespace mobot::emulate
