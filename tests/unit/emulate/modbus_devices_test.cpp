// The sensor bus's factory against the emulated bus on a pseudo-terminal: the config entry, the
// real libmodbus master, and the compass and sonar drivers the runtime polls.
#include "drivers/hardware/modbus_devices.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "drivers/sim/robot_profile.h"
#include "tests/unit/emulate/line_harness.h"
#include "tools/emulate/devices/modbus_sensor_bus_device.h"

namespace mobot::emulate {
namespace {

using drivers::BackendError;
using drivers::hardware::DeviceReader;
using drivers::hardware::HardwareAssembly;
using drivers::hardware::ModbusSensorBus;
using testing::eventually;

constexpr double kPi = std::numbers::pi;
constexpr double kHeadingOffset_rad = 0.7;

// What the backend builds the roles into; every member spelt out, as -Wextra wants.
HardwareAssembly assembly_of(const sim::RobotProfile& profile,
                             const drivers::BackendOptions& options) {
  return HardwareAssembly{profile, options, {}, {}, nullptr, {}};
}

class ModbusDevicesTest : public ::testing::Test {
 protected:
  ModbusDevicesTest() {
    world_.set_base_pose({0.0, 0.0, 0.3});
    ModbusSensorBusOptions options;
    options.heading_offset_rad = kHeadingOffset_rad;
    auto device = std::make_unique<ModbusSensorBusDevice>(world_, options, 11);
    model_ = device.get();
    harness_ = std::make_unique<testing::LineHarness>(std::move(device));
  }
  ~ModbusDevicesTest() override {
    // The bus's thread stops before the line goes.
    for (const auto& device : assembly_.devices) device->stop();
    harness_.reset();
  }

  // The entry as the backend hands it over: `driver` already read. A generous time-out: the
  // machine running the test may be busy, and a late reply is the test's scheduling.
  void make(const std::string& extra = "") {
    const YAML::Node node =
        YAML::Load("{driver: modbus_rtu, device: " + harness_->path().string() +
                   ", heading_offset_rad: 0.7, response_timeout_s: 0.1" + extra + "}");
    DeviceReader entry(node, "hardware.bus");
    std::string driver;
    entry.text("driver", driver);
    drivers::hardware::make_modbus_rtu(entry, assembly_);
  }
  void start() {
    for (const auto& device : assembly_.devices) device->start();
  }
  ModbusSensorBus& bus() { return dynamic_cast<ModbusSensorBus&>(*assembly_.devices.at(0)); }
  void change(const std::function<void(ModbusSensorBusDevice&)>& action) {
    harness_->with_line([&](DeviceLine&) { action(*model_); });
  }

  // The message of the error a config gives, or "" when it is accepted.
  std::string error_of(const std::string& yaml) {
    HardwareAssembly assembly = assembly_of(profile_, options_);
    const YAML::Node node = YAML::Load(yaml);
    DeviceReader entry(node, "hardware.bus");
    std::string driver;
    entry.text("driver", driver);
    try {
      drivers::hardware::make_modbus_rtu(entry, assembly);
    } catch (const BackendError& error) {
      return error.what();
    }
    return "";
  }

  testing::BoxWorld world_{-5.0, 2.3, -5.0, 1.30};
  ModbusSensorBusDevice* model_ = nullptr;
  std::unique_ptr<testing::LineHarness> harness_;
  sim::RobotProfile profile_ = sim::r1_profile();
  drivers::BackendOptions options_;
  HardwareAssembly assembly_ = assembly_of(profile_, options_);
};

TEST_F(ModbusDevicesTest, TheCompassHeadingArrivesThroughItsDriver) {
  make();
  start();
  auto& compass = *assembly_.drivers.compass;
  EXPECT_EQ(compass.name(), "compass");
  EXPECT_NEAR(compass.nominal_rate_hz(), 10.0, 1e-9);
  std::optional<msgs::CompassReading> reading;
  ASSERT_TRUE(eventually([&] { return (reading = compass.poll(12.5)).has_value(); }, 5.0))
      << compass.status().reason;
  EXPECT_TRUE(compass.status().ok) << compass.status().reason;
  // Stamped with the robot clock of the poll, and the offset turned back into the map heading
  // (1 degree of noise).
  EXPECT_EQ(reading->stamp_s, 12.5);
  EXPECT_NEAR(geometry::wrap_angle(reading->heading_rad - 0.3), 0.0, 0.07);
  // The same reading is not given twice; the next one comes at about 10 Hz.
  EXPECT_FALSE(compass.poll(12.51));
  int readings = 0;
  const double started_s = harness_->seconds();
  while (harness_->seconds() - started_s < 1.0) {
    if (compass.poll(13.0)) ++readings;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_NEAR(readings, 10, 3);
}

TEST_F(ModbusDevicesTest, TheSonarRingArrivesWithTheProfilesMounts) {
  make();
  start();
  auto& sonar = *assembly_.drivers.sonar;
  EXPECT_EQ(sonar.name(), "sonar");
  EXPECT_NEAR(sonar.nominal_rate_hz(), 10.0, 1e-9);
  std::optional<msgs::SonarRing> ring;
  ASSERT_TRUE(eventually([&] { return (ring = sonar.poll(3.0)).has_value(); }, 5.0))
      << sonar.status().reason;
  EXPECT_TRUE(sonar.status().ok) << sonar.status().reason;
  EXPECT_EQ(ring->stamp_s, 3.0);
  ASSERT_EQ(ring->readings.size(), 8u);
  for (std::size_t i = 0; i < 8; ++i) {
    const msgs::RangeReading& reading = ring->readings[i];
    EXPECT_EQ(reading.sensor_in_base.x, profile_.sonars_in_base[i].x);
    EXPECT_EQ(reading.sensor_in_base.theta, profile_.sonars_in_base[i].theta);
    EXPECT_NEAR(reading.cone_rad, kPi / 8, 1e-12);
    EXPECT_EQ(reading.range_min_m, 0.03);
    EXPECT_EQ(reading.range_max_m, 4.0);
  }
  // The left side sonars (at y = 0.30, along +y) are 1 m from the wall at y = 1.30; turned by
  // 0.3 rad the nearest ray of their cone is at 0.3 - 0.196 rad.
  for (const std::size_t left : {4u, 5u}) {
    const double along_m =
        1.30 - geometry::compose(world_.base_pose(), {left == 4 ? 0.15 : -0.15, 0.30, kPi / 2}).y;
    EXPECT_NEAR(ring->readings[left].range_m, along_m / std::cos(0.3 - kPi / 16), 0.08);
  }
  // The right side ones look at a wall 4.7 m away: no echo, the ring says range_max.
  EXPECT_EQ(ring->readings[6].range_m, 4.0);
  EXPECT_EQ(ring->readings[7].range_m, 4.0);

  // A ring only once every sonar was read again: about 10 a second.
  EXPECT_FALSE(sonar.poll(3.01));
  int rings = 0;
  const double started_s = harness_->seconds();
  while (harness_->seconds() - started_s < 1.0) {
    if (sonar.poll(4.0)) ++rings;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_NEAR(rings, 10, 3);
}

TEST_F(ModbusDevicesTest, ASilentSonarHoldsTheRingAndNamesItsNode) {
  make();
  start();
  auto& sonar = *assembly_.drivers.sonar;
  ASSERT_TRUE(eventually([&] { return sonar.poll(1.0).has_value(); }, 5.0));
  change([](ModbusSensorBusDevice& device) { device.set_node_present(5, false); });
  ASSERT_TRUE(eventually([&] { return !sonar.status().ok; }, 5.0));
  EXPECT_EQ(sonar.status().reason, "timeout (node 5)");
  EXPECT_TRUE(assembly_.drivers.compass->status().ok);
  // Nothing comes while node 5 stays silent.
  sonar.poll(2.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_FALSE(sonar.poll(2.5));

  change([](ModbusSensorBusDevice& device) { device.set_node_present(5, true); });
  EXPECT_TRUE(eventually([&] { return sonar.status().ok; }, 5.0));
  EXPECT_TRUE(eventually([&] { return sonar.poll(3.0).has_value(); }, 5.0));
}

TEST_F(ModbusDevicesTest, TheLimitSwitchAndTheCountersOfEachNode) {
  make();
  EXPECT_FALSE(bus().limit_switch_pressed());
  start();
  ASSERT_TRUE(eventually([&] { return bus().limit_switch_pressed() == false; }, 5.0));
  change([](ModbusSensorBusDevice& device) { device.set_limit_switch(true); });
  EXPECT_TRUE(eventually([&] { return bus().limit_switch_pressed() == true; }, 5.0));

  ASSERT_TRUE(eventually([&] { return assembly_.drivers.sonar->poll(1.0).has_value(); }, 5.0));
  const std::vector<drivers::DeviceCounters> counters = bus().counters();
  ASSERT_EQ(counters.size(), 11u);
  const std::vector<std::string> names{"bus",    "compass", "sonar2",      "sonar3",
                                       "sonar4", "sonar5",  "sonar6",      "sonar7",
                                       "sonar8", "sonar9",  "limit_switch"};
  std::uint64_t node_frames = 0;
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(counters[i].name, names[i]);
    EXPECT_TRUE(counters[i].status.ok) << names[i] << ": " << counters[i].status.reason;
    EXPECT_GT(counters[i].frames, 0u) << names[i];
    EXPECT_EQ(counters[i].checksum_errors, 0u) << names[i];
    if (i > 0) node_frames += counters[i].frames;
  }
  // The nodes' replies add up to the bus's (read at slightly different moments).
  EXPECT_NEAR(static_cast<double>(node_frames), static_cast<double>(counters[0].frames), 3.0);
  EXPECT_EQ(counters[1].bytes, 7 * counters[1].frames);
  EXPECT_EQ(counters[10].bytes, 6 * counters[10].frames);
}

TEST_F(ModbusDevicesTest, AMissingPortIsMissingOnBothDrivers) {
  const YAML::Node node =
      YAML::Load("{device: " + harness_->path().string() + "-not-there, response_timeout_s: 0.1}");
  DeviceReader entry(node, "hardware.bus");
  drivers::hardware::make_modbus_rtu(entry, assembly_);
  start();
  EXPECT_TRUE(eventually(
      [&] {
        return assembly_.drivers.compass->status().reason == "missing" &&
               assembly_.drivers.sonar->status().reason == "missing";
      },
      5.0));
  EXPECT_FALSE(assembly_.drivers.compass->poll(1.0));
  EXPECT_FALSE(assembly_.drivers.sonar->poll(1.0));
  EXPECT_EQ(bus().counters().at(0).status.reason, "missing");
}

TEST_F(ModbusDevicesTest, BadOptionsAreNamed) {
  EXPECT_EQ(error_of("{device: /dev/ttyUSB0}"), "");
  EXPECT_EQ(error_of("{device: /dev/ttyUSB0, sonar_nodes: [11, 12, 13, 14, 15, 16, 17, 18]}"), "");
  const auto error_names = [&](const std::string& yaml, const std::string& key) {
    const std::string error = error_of(yaml);
    EXPECT_NE(error.find(key), std::string::npos) << yaml << " gave '" << error << "'";
  };
  error_names("{baud: 115200}", "hardware.bus.device:");
  error_names("{device: /dev/ttyUSB0, baud: 12345}", "hardware.bus.baud:");
  error_names("{device: /dev/ttyUSB0, compass_node: 0}", "hardware.bus.compass_node:");
  error_names("{device: /dev/ttyUSB0, limit_switch_node: 248}", "hardware.bus.limit_switch_node:");
  error_names("{device: /dev/ttyUSB0, sonar_nodes: [2, 3]}", "hardware.bus.sonar_nodes: one node");
  error_names("{device: /dev/ttyUSB0, sonar_nodes: 2}", "hardware.bus.sonar_nodes:");
  error_names("{device: /dev/ttyUSB0, sonar_nodes: [2, 3, 4, 5, 6, 7, 8, x]}",
              "hardware.bus.sonar_nodes:");
  error_names("{device: /dev/ttyUSB0, sonar_nodes: [2, 3, 4, 5, 6, 7, 8, 300]}",
              "hardware.bus.sonar_nodes: 300");
  error_names("{device: /dev/ttyUSB0, sonar_nodes: [1, 3, 4, 5, 6, 7, 8, 9]}",
              "hardware.bus.sonar_nodes: node 1 is already used by compass_node");
  error_names("{device: /dev/ttyUSB0, sonar_nodes: [2, 3, 4, 5, 6, 7, 9, 9]}",
              "hardware.bus.sonar_nodes: node 9 is already used by sonar_nodes");
  error_names("{device: /dev/ttyUSB0, limit_switch_node: 2}",
              "hardware.bus.limit_switch_node: node 2");
  error_names("{device: /dev/ttyUSB0, heading_offset_rad: 7}", "hardware.bus.heading_offset_rad:");
  error_names("{device: /dev/ttyUSB0, response_timeout_s: 0}", "hardware.bus.response_timeout_s:");
  error_names("{device: /dev/ttyUSB0, compas_node: 1}", "hardware.bus.compas_node: unknown key");

  // A robot without sonars has no ring for the bus to read.
  const sim::RobotProfile bare;
  HardwareAssembly assembly = assembly_of(bare, options_);
  const YAML::Node node = YAML::Load("{device: /dev/ttyUSB0}");
  DeviceReader entry(node, "hardware.bus");
  EXPECT_THROW(drivers::hardware::make_modbus_rtu(entry, assembly), BackendError);
}

}  // namespace
}  // namespace mobot::emulate
