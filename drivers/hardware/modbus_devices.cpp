#include "drivers/hardware/modbus_devices.h"

#include <algorithm>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "drivers/modbus/modbus_frame_bytes.h"
#include "drivers/modbus/modbus_poll_schedule.h"

namespace mobot::drivers::hardware {
namespace {

// Modbus slave ids; 0 is the broadcast, which no slave answers.
constexpr int kFirstSlaveId = 1;
constexpr int kLastSlaveId = 247;
// The length of a reply to one read, as ModbusRtuBus counts it.
using modbus::kBitsReplyBytes;
using modbus::kExceptionReplyBytes;
using modbus::kRegisterReplyBytes;

std::string node_name(const modbus::NodeHealth& health) {
  switch (health.kind) {
    case modbus::NodeKind::kCompass:
      return "compass";
    case modbus::NodeKind::kSonar:
      return "sonar" + std::to_string(health.node);
    case modbus::NodeKind::kLimitSwitch:
      break;
  }
  return "limit_switch";
}

// A node's own counters, from what the schedule recorded of its reads. A node's status is its
// own failure when it has one, else the bus's: a node cannot be better than the line it is on.
DeviceCounters node_counters(const modbus::NodeHealth& health, const DeviceStatus& bus_status) {
  const std::uint64_t reply_bytes =
      health.kind == modbus::NodeKind::kLimitSwitch ? kBitsReplyBytes : kRegisterReplyBytes;
  const std::uint64_t good = health.reads - health.failures;
  const std::uint64_t bad_replies =
      health.failures - health.timeouts - health.crc_errors - health.exceptions;
  DeviceCounters counters;
  counters.name = node_name(health);
  counters.status = health.ok ? bus_status : DeviceStatus{false, health.reason};
  // Exceptions are replies too (the node is there and said no), as the bus counts them.
  counters.frames = good + health.exceptions;
  counters.bytes =
      (good + health.crc_errors) * reply_bytes + health.exceptions * kExceptionReplyBytes;
  counters.checksum_errors = health.crc_errors + bad_replies;
  return counters;
}

const modbus::NodeHealth* find_node(const std::vector<modbus::NodeHealth>& health, int node) {
  const auto found = std::find_if(health.begin(), health.end(),
                                  [node](const modbus::NodeHealth& h) { return h.node == node; });
  return found == health.end() ? nullptr : &*found;
}
// The pointer would dangle once the temporary is gone.
const modbus::NodeHealth* find_node(std::vector<modbus::NodeHealth>&& health, int node) = delete;

// The compass's newest heading, once per reading the bus brought.
class BusCompass final : public SensorDriver<msgs::CompassReading> {
 public:
  BusCompass(const modbus::ModbusRtuBus& bus, double rate_hz) : bus_(bus), rate_hz_(rate_hz) {}

  std::string_view name() const override { return "compass"; }
  double nominal_rate_hz() const override { return rate_hz_; }

  std::optional<msgs::CompassReading> poll(double now_s) override {
    const std::optional<modbus::CompassSample> sample = bus_.compass();
    if (!sample || sample->count == taken_count_) return std::nullopt;
    taken_count_ = sample->count;
    // The robot clock, not the bus's: the reading is at most one control period old here.
    return msgs::CompassReading{.stamp_s = now_s, .heading_rad = sample->heading_rad};
  }

  DeviceStatus status() const override {
    const DeviceStatus bus_status = bus_.status();
    if (!bus_status.ok) return bus_status;
    const std::vector<modbus::NodeHealth> health = bus_.node_health();
    const modbus::NodeHealth* node = find_node(health, bus_.options().compass_node);
    if (node != nullptr && !node->ok) return {false, node->reason};
    return {};
  }

 private:
  const modbus::ModbusRtuBus& bus_;
  double rate_hz_;
  std::uint64_t taken_count_ = 0;
};

// The sonar ring: every sonar's newest range, once each of them was read again.
class BusSonarRing final : public SensorDriver<msgs::SonarRing> {
 public:
  BusSonarRing(const modbus::ModbusRtuBus& bus, const sim::RobotProfile& profile, double rate_hz)
      : bus_(bus), rate_hz_(rate_hz), taken_counts_(bus.options().sonar_nodes.size(), 0) {
    for (const geometry::Pose2D& pose : profile.sonars_in_base) {
      msgs::RangeReading reading;
      reading.sensor_in_base = pose;
      reading.cone_rad = profile.sonar_cone_rad;
      reading.range_min_m = profile.sonar_range_min_m;
      reading.range_max_m = profile.sonar_range_max_m;
      reading.range_m = profile.sonar_range_max_m;
      mounts_.push_back(reading);
    }
  }

  std::string_view name() const override { return "sonar"; }
  double nominal_rate_hz() const override { return rate_hz_; }

  // A ring only when every sonar has a reading newer than the last ring's. A sonar that stopped
  // answering holds the ring back rather than leaving a stale range in it: the status names the
  // node, and the robot stops instead of driving with one side blind.
  std::optional<msgs::SonarRing> poll(double now_s) override {
    const std::vector<std::optional<modbus::SonarSample>> samples = bus_.sonars();
    for (std::size_t i = 0; i < samples.size(); ++i) {
      if (!samples[i] || samples[i]->count == taken_counts_[i]) return std::nullopt;
    }
    msgs::SonarRing ring;
    ring.stamp_s = now_s;
    ring.readings = mounts_;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      taken_counts_[i] = samples[i]->count;
      msgs::RangeReading& reading = ring.readings[i];
      // The SRF05 says 0 (no echo) past its 4 m, and its nearest is 3 cm; the clamp keeps a
      // firmware's stray value within the limits the ring advertises.
      reading.range_m = std::clamp(samples[i]->range_m.value_or(reading.range_max_m),
                                   reading.range_min_m, reading.range_max_m);
    }
    return ring;
  }

  DeviceStatus status() const override {
    const DeviceStatus bus_status = bus_.status();
    if (!bus_status.ok) return bus_status;
    const std::vector<modbus::NodeHealth> health = bus_.node_health();
    for (const int node_id : bus_.options().sonar_nodes) {
      const modbus::NodeHealth* node = find_node(health, node_id);
      if (node != nullptr && !node->ok) {
        return {false, node->reason + " (node " + std::to_string(node_id) + ")"};
      }
    }
    return {};
  }

 private:
  const modbus::ModbusRtuBus& bus_;
  double rate_hz_;
  std::vector<msgs::RangeReading> mounts_;  // in the order of sonar_nodes
  std::vector<std::uint64_t> taken_counts_;
};

std::vector<int> read_sonar_nodes(DeviceReader& entry, std::size_t sonar_count) {
  std::vector<int> nodes;
  for (std::size_t i = 0; i < sonar_count; ++i) nodes.push_back(2 + static_cast<int>(i));
  const YAML::Node configured = entry.node("sonar_nodes");
  if (!configured) return nodes;
  if (!configured.IsSequence()) {
    throw BackendError(entry.path() + ".sonar_nodes: expected a list of slave ids");
  }
  try {
    nodes = configured.as<std::vector<int>>();
  } catch (const YAML::Exception&) {
    throw BackendError(entry.path() + ".sonar_nodes: expected a list of slave ids");
  }
  if (nodes.size() != sonar_count) {
    throw BackendError(entry.path() + ".sonar_nodes: one node per sonar of the robot (" +
                       std::to_string(sonar_count) + "), got " + std::to_string(nodes.size()));
  }
  for (const int node : nodes) {
    if (node < kFirstSlaveId || node > kLastSlaveId) {
      throw BackendError(entry.path() + ".sonar_nodes: " + std::to_string(node) +
                         " is not a slave id (1..247)");
    }
  }
  return nodes;
}

// Every node answers to its own id: two nodes on one id would both answer and garble the reply.
void check_distinct(const DeviceReader& entry, const modbus::ModbusRtuBusOptions& options) {
  std::vector<std::pair<int, std::string>> seen{{options.compass_node, "compass_node"}};
  const auto add = [&](int node, const std::string& key) {
    for (const auto& [other, other_key] : seen) {
      if (other == node) {
        throw BackendError(entry.path() + "." + key + ": node " + std::to_string(node) +
                           " is already used by " + other_key);
      }
    }
    seen.emplace_back(node, key);
  };
  for (const int node : options.sonar_nodes) add(node, "sonar_nodes");
  add(options.limit_switch_node, "limit_switch_node");
}

}  // namespace

std::vector<DeviceCounters> ModbusSensorBus::counters() const {
  const DeviceStatus bus_status = bus_.status();
  std::vector<DeviceCounters> out{bus_.device_counters("bus")};
  for (const modbus::NodeHealth& health : bus_.node_health()) {
    out.push_back(node_counters(health, bus_status));
  }
  return out;
}

std::optional<bool> ModbusSensorBus::limit_switch_pressed() const {
  const std::optional<modbus::LimitSwitchSample> sample = bus_.limit_switch();
  if (!sample || !bus_.status().ok) return std::nullopt;
  const std::vector<modbus::NodeHealth> health = bus_.node_health();
  const modbus::NodeHealth* node = find_node(health, bus_.options().limit_switch_node);
  if (node != nullptr && !node->ok) return std::nullopt;
  return sample->pressed;
}

void make_modbus_rtu(DeviceReader& entry, HardwareAssembly& assembly) {
  const sim::RobotProfile& profile = assembly.profile;
  if (profile.sonars_in_base.empty()) {
    throw BackendError(entry.path() + ": this robot profile has no sonar ring for the bus");
  }
  const serial::SerialOptions serial = read_serial_options(entry, 115200);
  modbus::ModbusRtuBusOptions options;
  options.device_path = serial.device;
  options.baud = static_cast<int>(serial.baud);
  entry.integer("compass_node", options.compass_node, kFirstSlaveId, kLastSlaveId);
  options.sonar_nodes = read_sonar_nodes(entry, profile.sonars_in_base.size());
  entry.integer("limit_switch_node", options.limit_switch_node, kFirstSlaveId, kLastSlaveId);
  entry.number("heading_offset_rad", options.heading_offset_rad, -2.0 * std::numbers::pi,
               2.0 * std::numbers::pi);
  // A USB adapter's latency timer (16 ms on an FTDI by default) can eat most of the 20 ms.
  entry.number("response_timeout_s", options.response_timeout_s, 0.001, 1.0);
  entry.done();
  check_distinct(entry, options);
  options.compass_rate_hz = assembly.options.compass_rate_hz;
  options.sonar_rate_hz = assembly.options.sonar_rate_hz;

  std::unique_ptr<ModbusSensorBus> device;
  try {
    device = std::make_unique<ModbusSensorBus>(options);
  } catch (const std::invalid_argument& error) {
    // The node ids and time-outs were checked above; what is left for the bus to refuse is a
    // baud rate it cannot set.
    const std::string why = error.what();
    const bool baud = why.find("baud") != std::string::npos;
    throw BackendError(entry.path() + (baud ? ".baud" : "") + ": " + why);
  }
  const modbus::ModbusRtuBus& bus = device->bus();
  // The watchdog expects readings at the pace the bus really reads, not the configured one.
  assembly.drivers.compass =
      std::make_unique<BusCompass>(bus, bus.effective_rate_hz(modbus::NodeKind::kCompass));
  assembly.drivers.sonar =
      std::make_unique<BusSonarRing>(bus, profile, bus.effective_rate_hz(modbus::NodeKind::kSonar));
  assembly.devices.push_back(std::move(device));
}

}  // namespace mobot::drivers::hardware
