#include "drivers/modbus/modbus_rtu_bus.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/geometry/pose2d.h"
#include "tests/unit/emulate/line_harness.h"
#include "tools/emulate/devices/modbus_sensor_bus_device.h"

namespace mobot::drivers::modbus {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kPi = std::numbers::pi;

// The model and the lock that lets the test change it while the pty thread drives it.
struct SharedDevice {
  std::mutex mutex;
  emulate::ModbusSensorBusDevice device;
  Clock::time_point epoch = Clock::now();

  template <class Change>
  void change(Change&& change) {
    const std::lock_guard lock(mutex);
    change(device);
  }
  double now_s() const { return std::chrono::duration<double>(Clock::now() - epoch).count(); }
};

// A pseudo-terminal standing for the serial port: the bus opens its slave end by path, and a
// thread carries bytes between the master end and the model on the steady clock.
class PtyBridge {
 public:
  explicit PtyBridge(SharedDevice& shared) : shared_(shared) {
    std::array<char, 256> name{};
    if (openpty(&master_fd_, &slave_fd_, name.data(), nullptr, nullptr) == -1) {
      throw std::runtime_error("openpty failed");
    }
    slave_path_ = name.data();
    // Raw from the start: the line discipline's echo would hand the model its own replies.
    termios settings{};
    tcgetattr(slave_fd_, &settings);
    cfmakeraw(&settings);
    tcsetattr(slave_fd_, TCSANOW, &settings);
    thread_ = std::jthread([this](const std::stop_token& stop) { run(stop); });
  }

  // Pulls the plug: the slave's path goes with the master end.
  ~PtyBridge() {
    thread_.request_stop();
    thread_.join();
    ::close(master_fd_);
    ::close(slave_fd_);
  }
  PtyBridge(const PtyBridge&) = delete;
  PtyBridge& operator=(const PtyBridge&) = delete;

  const std::string& slave_path() const { return slave_path_; }

 private:
  void run(const std::stop_token& stop) {
    std::array<std::uint8_t, 512> buffer{};
    while (!stop.stop_requested()) {
      pollfd ready{.fd = master_fd_, .events = POLLIN, .revents = 0};
      ::poll(&ready, 1, 1);
      std::vector<std::uint8_t> reply;
      {
        const std::lock_guard lock(shared_.mutex);
        if ((ready.revents & POLLIN) != 0) {
          const ssize_t count = ::read(master_fd_, buffer.data(), buffer.size());
          if (count > 0) {
            shared_.device.receive(
                std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(count)),
                shared_.now_s());
          }
        }
        reply = shared_.device.transmit(shared_.now_s());
      }
      std::size_t written = 0;
      while (written < reply.size()) {
        const ssize_t count = ::write(master_fd_, reply.data() + written, reply.size() - written);
        if (count <= 0) break;
        written += static_cast<std::size_t>(count);
      }
    }
  }

  SharedDevice& shared_;
  int master_fd_ = -1;
  int slave_fd_ = -1;
  std::string slave_path_;
  std::jthread thread_;
};

bool eventually(const std::function<bool()>& condition, double timeout_s = 5.0) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  while (Clock::now() < deadline) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return condition();
}

NodeHealth health_of(const std::vector<NodeHealth>& health, int node) {
  for (const NodeHealth& entry : health) {
    if (entry.node == node) return entry;
  }
  throw std::out_of_range("no such node");
}

class ModbusRtuBusTest : public ::testing::Test {
 protected:
  static constexpr double kHeadingOffset_rad = 0.7;

  ModbusRtuBusTest() {
    world_.set_base_pose({0.0, 0.0, 0.3});
    std::string directory = (std::filesystem::temp_directory_path() / "mobot_modbus_XXXXXX");
    if (mkdtemp(directory.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    directory_ = directory;
    link_path_ = directory_ / "sensor_bus";
    plug_in();
  }

  ~ModbusRtuBusTest() override {
    bus_.reset();
    bridge_.reset();
    std::filesystem::remove_all(directory_);
  }

  static emulate::ModbusSensorBusOptions model_options() {
    emulate::ModbusSensorBusOptions options;
    options.heading_offset_rad = kHeadingOffset_rad;
    return options;
  }

  // Generous time-outs: the machine running the test may be busy, and a late reply here is
  // the test's scheduling, not the bus's.
  ModbusRtuBusOptions bus_options() const {
    ModbusRtuBusOptions options;
    options.device_path = link_path_.string();
    options.heading_offset_rad = kHeadingOffset_rad;
    options.response_timeout_s = 0.1;
    options.silent_timeout_s = 0.4;
    options.reopen_period_s = 0.1;
    options.retry_period_s = 0.3;
    return options;
  }

  // A new pty, and the symlink the bus opens re-pointed at it (as udev does for a port that
  // comes back under another name).
  void plug_in() {
    bridge_ = std::make_unique<PtyBridge>(shared_);
    const std::filesystem::path staged = directory_ / "sensor_bus.new";
    std::filesystem::create_symlink(bridge_->slave_path(), staged);
    std::filesystem::rename(staged, link_path_);
  }
  void unplug() { bridge_.reset(); }

  void start(const ModbusRtuBusOptions& options) {
    bus_ = std::make_unique<ModbusRtuBus>(options);
    bus_->start();
  }

  bool status_is(const std::string& reason) const {
    const DeviceStatus status = bus_->status();
    return reason.empty() ? status.ok : !status.ok && status.reason == reason;
  }

  bool all_nodes(const std::string& reason) const {
    for (const NodeHealth& health : bus_->node_health()) {
      if (reason.empty() ? !health.ok : health.ok || health.reason != reason) return false;
    }
    return true;
  }

  emulate::testing::BoxWorld world_{-5.0, 2.3, -5.0, 1.30};
  SharedDevice shared_{.mutex = {}, .device = {world_, model_options(), 11}};
  std::filesystem::path directory_;
  std::filesystem::path link_path_;
  std::unique_ptr<PtyBridge> bridge_;
  std::unique_ptr<ModbusRtuBus> bus_;
};

TEST_F(ModbusRtuBusTest, TheReadingsOfAllTenNodesArrive) {
  start(bus_options());
  ASSERT_TRUE(eventually([this] { return status_is("") && all_nodes(""); }))
      << bus_->status().reason;
  ASSERT_TRUE(eventually([this] {
    const auto sonars = bus_->sonars();
    return bus_->compass() && bus_->limit_switch() &&
           std::all_of(sonars.begin(), sonars.end(), [](const auto& s) { return s.has_value(); });
  }));

  // The compass's clockwise reading and the offset turned back into the map heading (1 degree
  // of noise).
  EXPECT_NEAR(geometry::wrap_angle(bus_->compass()->heading_rad - 0.3), 0.0, 0.07);
  const std::vector<std::optional<SonarSample>> sonars = bus_->sonars();
  ASSERT_EQ(sonars.size(), 8u);
  // The left side sonars (at y = 0.30, along +y) are 1 m from the wall at y = 1.30; turned by
  // 0.3 rad the nearest ray of their cone is at 0.3 - 0.196 rad: 1 m / cos(0.104).
  for (const std::size_t left : {4u, 5u}) {
    ASSERT_TRUE(sonars[left]->range_m);
    const double along_m =
        (1.30 - geometry::compose(world_.base_pose(), {left == 4 ? 0.15 : -0.15, 0.30, kPi / 2}).y);
    EXPECT_NEAR(*sonars[left]->range_m, along_m / std::cos(0.3 - kPi / 16), 0.08);
  }
  // The right side ones look at a wall 4.7 m away: no echo.
  EXPECT_FALSE(sonars[6]->range_m);
  EXPECT_FALSE(sonars[7]->range_m);
  for (const std::size_t front : {0u, 1u, 2u, 3u}) {
    ASSERT_TRUE(sonars[front]->range_m);
    EXPECT_GT(*sonars[front]->range_m, 0.5);
    EXPECT_LT(*sonars[front]->range_m, 4.0);
  }

  EXPECT_FALSE(bus_->limit_switch()->pressed);
  shared_.change([](emulate::ModbusSensorBusDevice& device) { device.set_limit_switch(true); });
  EXPECT_TRUE(eventually([this] { return bus_->limit_switch()->pressed; }));

  // The rates: 10 Hz compass and sonars, 20 Hz limit switch.
  const std::uint64_t compass_before = bus_->compass()->count;
  const std::uint64_t sonar_before = bus_->sonars()[3]->count;
  const std::uint64_t switch_before = bus_->limit_switch()->count;
  std::this_thread::sleep_for(std::chrono::seconds(2));
  EXPECT_NEAR(static_cast<double>(bus_->compass()->count - compass_before), 20.0, 3.0);
  EXPECT_NEAR(static_cast<double>(bus_->sonars()[3]->count - sonar_before), 20.0, 3.0);
  EXPECT_NEAR(static_cast<double>(bus_->limit_switch()->count - switch_before), 40.0, 4.0);

  const ModbusBusCounters counters = bus_->counters();
  EXPECT_GT(counters.requests, 200u);
  EXPECT_GE(counters.replies + counters.timeouts, counters.requests - 1);
  EXPECT_EQ(counters.crc_errors, 0u);
  EXPECT_EQ(counters.reconnects, 0u);
  const DeviceCounters metrics = bus_->device_counters("sensor_bus");
  EXPECT_EQ(metrics.name, "sensor_bus");
  EXPECT_TRUE(metrics.status.ok);
  EXPECT_GE(metrics.frames, counters.replies);
  // Register replies are 7 bytes, the limit switch's 6.
  EXPECT_GE(metrics.bytes, 6 * metrics.frames);
  EXPECT_LE(metrics.bytes, 7 * metrics.frames);
}

TEST_F(ModbusRtuBusTest, OneRoundOfTheTenNodesBackToBack) {
  // Rates far above what the bus carries, and the whole bus allowed: the master reads without
  // pause, so the time a read takes shows.
  ModbusRtuBusOptions options = bus_options();
  options.response_timeout_s = 0.02;
  options.compass_rate_hz = 1000.0;
  options.sonar_rate_hz = 1000.0;
  options.limit_switch_rate_hz = 1000.0;
  options.max_bus_load = 1.0;
  // Estimated reads shorter than the real ones keep the master always behind.
  options.turnaround_s = 0.0;
  start(options);
  ASSERT_TRUE(eventually([this] { return status_is(""); }));
  const ModbusBusCounters before = bus_->counters();
  const auto started = Clock::now();
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const ModbusBusCounters after = bus_->counters();
  const double elapsed_s = std::chrono::duration<double>(Clock::now() - started).count();
  const double reads = static_cast<double>(after.requests - before.requests);
  const double round_s = 10.0 * elapsed_s / reads;
  std::cout << "one round of 10 reads over the pty at 115200 baud: " << round_s * 1e3
            << " ms (wire and turnaround estimate " << bus_->round_s() * 1e3 << " ms), "
            << after.timeouts - before.timeouts << " time-outs in " << reads << " reads\n";
  RecordProperty("round_ms", std::to_string(round_s * 1e3));
  EXPECT_GT(reads, 100.0);
  // The model alone needs 10 * 1.75 ms of silence and 69 reply bytes: 23.5 ms.
  EXPECT_GT(round_s, 0.023);
  EXPECT_LT(round_s, 0.2);
}

TEST_F(ModbusRtuBusTest, ARemovedNodeTimesOutAndComesBack) {
  start(bus_options());
  ASSERT_TRUE(eventually([this] { return status_is("") && all_nodes(""); }));
  shared_.change([](emulate::ModbusSensorBusDevice& device) { device.set_node_present(5, false); });
  ASSERT_TRUE(eventually([this] {
    const NodeHealth health = health_of(bus_->node_health(), 5);
    return !health.ok && health.reason == "timeout";
  }));
  EXPECT_TRUE(health_of(bus_->node_health(), 4).ok);
  EXPECT_TRUE(status_is(""));
  EXPECT_GE(bus_->counters().timeouts, 3u);

  shared_.change([](emulate::ModbusSensorBusDevice& device) { device.set_node_present(5, true); });
  EXPECT_TRUE(eventually([this] { return health_of(bus_->node_health(), 5).ok; }));
}

TEST_F(ModbusRtuBusTest, ABusWithNoNodeLeftIsSilent) {
  start(bus_options());
  ASSERT_TRUE(eventually([this] { return status_is(""); }));
  shared_.change([](emulate::ModbusSensorBusDevice& device) {
    for (int node = 1; node <= 10; ++node) device.set_node_present(node, false);
  });
  EXPECT_TRUE(eventually([this] { return status_is("silent") && all_nodes("timeout"); }));
  shared_.change([](emulate::ModbusSensorBusDevice& device) {
    for (int node = 1; node <= 10; ++node) device.set_node_present(node, true);
  });
  EXPECT_TRUE(eventually([this] { return status_is("") && all_nodes(""); }));
}

TEST_F(ModbusRtuBusTest, BadChecksumsGiveCrc) {
  start(bus_options());
  ASSERT_TRUE(eventually([this] { return status_is(""); }));
  shared_.change([](emulate::ModbusSensorBusDevice& device) { device.set_bad_checksums(true); });
  EXPECT_TRUE(eventually([this] { return status_is("crc") && all_nodes("crc"); }))
      << bus_->status().reason;
  EXPECT_GT(bus_->counters().crc_errors, 10u);
  shared_.change([](emulate::ModbusSensorBusDevice& device) { device.set_bad_checksums(false); });
  EXPECT_TRUE(eventually([this] { return status_is("") && all_nodes(""); }));
}

TEST_F(ModbusRtuBusTest, AnExceptionIsTheNodesReason) {
  // Compass and limit switch swapped: each gets a read of a table it does not have.
  ModbusRtuBusOptions options = bus_options();
  options.compass_node = 10;
  options.limit_switch_node = 1;
  start(options);
  EXPECT_TRUE(eventually([this] {
    const std::vector<NodeHealth> health = bus_->node_health();
    return health_of(health, 1).reason == "exception 2" &&
           health_of(health, 10).reason == "exception 2" && health_of(health, 2).ok;
  }));
  EXPECT_TRUE(status_is(""));
  EXPECT_GE(bus_->counters().exceptions, 6u);
  EXPECT_FALSE(bus_->compass());
}

TEST_F(ModbusRtuBusTest, AnUnpluggedPortIsMissingUntilItComesBack) {
  start(bus_options());
  ASSERT_TRUE(eventually([this] { return status_is("") && bus_->compass(); }));
  unplug();
  ASSERT_TRUE(eventually([this] { return status_is("missing") && all_nodes("missing"); }))
      << bus_->status().reason;
  EXPECT_GE(bus_->counters().link_errors, 1u);
  EXPECT_TRUE(eventually([this] { return bus_->counters().open_failures >= 2; }));

  const std::uint64_t compass_before = bus_->compass()->count;
  plug_in();
  EXPECT_TRUE(eventually([this] { return status_is("") && all_nodes(""); }))
      << bus_->status().reason;
  EXPECT_GT(bus_->compass()->count, compass_before);
  EXPECT_EQ(bus_->counters().reconnects, 1u);
}

TEST_F(ModbusRtuBusTest, APortThatIsNotThereIsMissingAndStopSaysStopped) {
  ModbusRtuBusOptions options = bus_options();
  options.device_path = (directory_ / "nothing_here").string();
  start(options);
  EXPECT_TRUE(eventually([this] { return bus_->counters().open_failures >= 2; }));
  EXPECT_TRUE(status_is("missing"));
  bus_->stop();
  EXPECT_TRUE(status_is("stopped"));
}

TEST(ModbusRtuBus, RejectsOptionsItCannotUse) {
  ModbusRtuBusOptions no_path;
  EXPECT_THROW(ModbusRtuBus{no_path}, std::invalid_argument);
  ModbusRtuBusOptions odd_baud;
  odd_baud.device_path = "/dev/null";
  odd_baud.baud = 12345;
  EXPECT_THROW(ModbusRtuBus{odd_baud}, std::invalid_argument);
  ModbusRtuBusOptions no_timeout;
  no_timeout.device_path = "/dev/null";
  no_timeout.response_timeout_s = 0.0;
  EXPECT_THROW(ModbusRtuBus{no_timeout}, std::invalid_argument);
  ModbusRtuBusOptions repeated;
  repeated.device_path = "/dev/null";
  repeated.compass_node = 2;
  EXPECT_THROW(ModbusRtuBus{repeated}, std::invalid_argument);
  ModbusRtuBusOptions fine;
  fine.device_path = "/dev/null";
  const ModbusRtuBus bus(fine);
  EXPECT_EQ(bus.status().reason, "stopped");
}

}  // namespace
}  // namespace mobot::drivers::modbus
