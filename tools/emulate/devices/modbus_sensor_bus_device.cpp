#include "tools/emulate/devices/modbus_sensor_bus_device.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace mobot::emulate {
namespace {

constexpr std::uint8_t kReadDiscreteInputs = 0x02;
constexpr std::uint8_t kReadHoldingRegisters = 0x03;
constexpr std::uint8_t kReadInputRegisters = 0x04;
constexpr std::uint8_t kExceptionFlag = 0x80;
constexpr std::uint8_t kIllegalFunction = 0x01;
constexpr std::uint8_t kIllegalDataAddress = 0x02;
constexpr std::uint8_t kIllegalDataValue = 0x03;
// The spec's limits on one read's quantity.
constexpr int kMaxReadBits = 2000;
constexpr int kMaxReadRegisters = 125;
constexpr double kBitsPerByte = 10.0;  // 8N1
// Above 19200 baud the spec fixes t3.5 instead of scaling it with the byte time.
constexpr int kFixedSilenceAboveBaud = 19200;
constexpr double kFixedT35_s = 0.00175;

enum class Framing { kPending, kDead, kComplete };

struct Candidate {
  Framing framing = Framing::kPending;
  std::size_t length = 0;
};

// The request that would start at `start`: its length once the bytes that tell it are in.
Candidate candidate_at(const std::vector<std::uint8_t>& buffer, std::size_t start) {
  const std::size_t available = buffer.size() - start;
  if (available < 2) return {};
  std::size_t length = 0;
  switch (buffer[start + 1]) {
    case 0x01:
    case 0x02:
    case 0x03:
    case 0x04:
    case 0x05:
    case 0x06:
    case 0x08:
      length = 8;
      break;
    case 0x07:
    case 0x0B:
    case 0x0C:
    case 0x11:
      length = 4;
      break;
    case 0x16:
      length = 10;
      break;
    case 0x0F:
    case 0x10:
      if (available < 7) return {};
      length = 9 + std::size_t{buffer[start + 6]};
      break;
    case 0x17:
      if (available < 11) return {};
      length = 13 + std::size_t{buffer[start + 10]};
      break;
    default:
      return {Framing::kDead, 0};
  }
  if (available < length) return {Framing::kPending, length};
  const std::uint16_t crc =
      modbus_crc16(std::span<const std::uint8_t>(buffer).subspan(start, length - 2));
  const bool crc_ok =
      buffer[start + length - 2] == (crc & 0xFF) && buffer[start + length - 1] == (crc >> 8);
  return {crc_ok ? Framing::kComplete : Framing::kDead, length};
}

void append_crc(std::vector<std::uint8_t>& frame, bool spoil) {
  std::uint16_t crc = modbus_crc16(frame);
  // Every bit flipped: no chance the spoiled CRC matches by accident.
  if (spoil) crc ^= 0xFFFF;
  frame.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  frame.push_back(static_cast<std::uint8_t>(crc >> 8));
}

void check(const ModbusSensorBusOptions& options) {
  std::set<int> ids;
  std::vector<int> all = options.sonar_nodes;
  all.push_back(options.compass_node);
  all.push_back(options.limit_switch_node);
  for (const int id : all) {
    if (id < 1 || id > 247) throw std::invalid_argument("modbus sensor bus: slave ids are 1..247");
    if (!ids.insert(id).second) {
      throw std::invalid_argument("modbus sensor bus: a slave id repeats");
    }
  }
  if (options.sonar_poses.size() != options.sonar_nodes.size()) {
    throw std::invalid_argument("modbus sensor bus: one mounting pose per sonar");
  }
  const auto positive = [](double value) { return std::isfinite(value) && value > 0.0; };
  const auto non_negative = [](double value) { return std::isfinite(value) && value >= 0.0; };
  if (options.baud <= 0 || options.sonar_rays < 1 || !positive(options.sonar_max_m) ||
      !non_negative(options.sonar_min_m) || options.sonar_min_m >= options.sonar_max_m ||
      !non_negative(options.sonar_cone_rad) || !non_negative(options.sonar_height_m) ||
      !non_negative(options.compass_noise_rad) || !non_negative(options.sonar_noise_fraction) ||
      !std::isfinite(options.heading_offset_rad) ||
      (options.reply_delay_s && !non_negative(*options.reply_delay_s))) {
    throw std::invalid_argument(
        "modbus sensor bus: baud, rays and ranges must be positive, noise and delays >= 0");
  }
}

}  // namespace

std::uint16_t modbus_crc16(std::span<const std::uint8_t> bytes) {
  std::uint16_t crc = 0xFFFF;
  for (const std::uint8_t byte : bytes) {
    crc ^= byte;
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 1) != 0 ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001)
                           : static_cast<std::uint16_t>(crc >> 1);
    }
  }
  return crc;
}

std::vector<std::vector<std::uint8_t>> ModbusRtuRequestFramer::push(
    std::span<const std::uint8_t> bytes) {
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
  std::vector<std::vector<std::uint8_t>> frames;
  for (;;) {
    // Everything before the first position that may still start a request is garbage. No
    // request is longer than 268 bytes, so the buffer never holds more than that of them.
    std::size_t dead_prefix = 0;
    bool blocked = false;
    std::optional<std::size_t> found;
    std::size_t found_length = 0;
    for (std::size_t start = 0; start < buffer_.size(); ++start) {
      const Candidate candidate = candidate_at(buffer_, start);
      if (candidate.framing == Framing::kComplete) {
        found = start;
        found_length = candidate.length;
        break;
      }
      if (candidate.framing == Framing::kPending) blocked = true;
      if (!blocked) dead_prefix = start + 1;
    }
    if (!found) {
      buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(dead_prefix));
      discarded_bytes_ += dead_prefix;
      return frames;
    }
    const auto begin = buffer_.begin() + static_cast<std::ptrdiff_t>(*found);
    frames.emplace_back(begin, begin + static_cast<std::ptrdiff_t>(found_length));
    buffer_.erase(buffer_.begin(), begin + static_cast<std::ptrdiff_t>(found_length));
    discarded_bytes_ += *found;
  }
}

ModbusSensorBusDevice::ModbusSensorBusDevice(const EmulatedWorld& world,
                                             const ModbusSensorBusOptions& options,
                                             std::uint64_t seed)
    : world_(world), options_(options), rng_(seed) {
  check(options_);
  byte_s_ = kBitsPerByte / options_.baud;
  reply_delay_s_ = options_.reply_delay_s.value_or(
      options_.baud > kFixedSilenceAboveBaud ? kFixedT35_s : 3.5 * byte_s_);
}

void ModbusSensorBusDevice::set_node_present(int node, bool present) {
  const bool on_bus = node == options_.compass_node || node == options_.limit_switch_node ||
                      std::find(options_.sonar_nodes.begin(), options_.sonar_nodes.end(), node) !=
                          options_.sonar_nodes.end();
  if (!on_bus) {
    throw std::invalid_argument("modbus sensor bus: slave " + std::to_string(node) +
                                " is not on the bus");
  }
  if (present) {
    absent_nodes_.erase(node);
  } else {
    absent_nodes_.insert(node);
  }
}

void ModbusSensorBusDevice::receive(std::span<const std::uint8_t> bytes, double now_s) {
  now_s_ = std::max(now_s_, now_s);
  for (const std::vector<std::uint8_t>& request : framer_.push(bytes)) {
    ++requests_;
    if (std::optional<std::vector<std::uint8_t>> reply = answer(request)) {
      ++replies_;
      queue_reply(std::move(*reply), now_s_);
    }
  }
}

std::vector<std::uint8_t> ModbusSensorBusDevice::transmit(double now_s) {
  now_s_ = std::max(now_s_, now_s);
  std::vector<std::uint8_t> sent;
  while (!outgoing_.empty() && outgoing_.front().due_s <= now_s_) {
    sent.push_back(outgoing_.front().byte);
    outgoing_.pop_front();
  }
  return sent;
}

std::optional<std::vector<std::uint8_t>> ModbusSensorBusDevice::answer(
    std::span<const std::uint8_t> request) {
  const int node = request[0];
  if (absent_nodes_.contains(node)) return std::nullopt;
  const bool compass = node == options_.compass_node;
  const bool limit_switch = node == options_.limit_switch_node;
  const auto sonar_it = std::find(options_.sonar_nodes.begin(), options_.sonar_nodes.end(), node);
  const bool sonar = sonar_it != options_.sonar_nodes.end();
  // The broadcast address (0) falls out here too: no read is answered to a broadcast.
  if (!compass && !limit_switch && !sonar) return std::nullopt;

  const std::uint8_t function = request[1];
  std::vector<std::uint8_t> reply = {request[0], function};
  const auto exception = [&](std::uint8_t code) {
    reply = {request[0], static_cast<std::uint8_t>(function | kExceptionFlag), code};
    append_crc(reply, bad_checksums_);
    return reply;
  };
  if (function != kReadDiscreteInputs && function != kReadHoldingRegisters &&
      function != kReadInputRegisters) {
    return exception(kIllegalFunction);
  }
  const int start = (request[2] << 8) | request[3];
  const int quantity = (request[4] << 8) | request[5];

  if (function == kReadDiscreteInputs) {
    if (quantity < 1 || quantity > kMaxReadBits) return exception(kIllegalDataValue);
    const int inputs = limit_switch ? 1 : 0;
    if (start + quantity > inputs) return exception(kIllegalDataAddress);
    reply.push_back(1);
    reply.push_back(limit_switch_pressed_ ? 1 : 0);
  } else {
    if (quantity < 1 || quantity > kMaxReadRegisters) return exception(kIllegalDataValue);
    const int registers = limit_switch ? 0 : 1;
    if (start + quantity > registers) return exception(kIllegalDataAddress);
    const std::uint16_t value =
        compass ? compass_register()
                : sonar_register(static_cast<std::size_t>(sonar_it - options_.sonar_nodes.begin()));
    reply.push_back(2);
    reply.push_back(static_cast<std::uint8_t>(value >> 8));
    reply.push_back(static_cast<std::uint8_t>(value & 0xFF));
  }
  append_crc(reply, bad_checksums_);
  return reply;
}

std::uint16_t ModbusSensorBusDevice::compass_register() {
  // The CMPS03 turns clockwise, the map counter-clockwise: reading = offset - map heading.
  double clockwise_rad = options_.heading_offset_rad - world_.base_pose().theta;
  if (options_.compass_noise_rad > 0.0) {
    clockwise_rad += std::normal_distribution<double>(0.0, options_.compass_noise_rad)(rng_);
  }
  const double degrees = clockwise_rad * 180.0 / std::numbers::pi;
  const long tenths = std::lround(degrees * 10.0) % 3600;
  return static_cast<std::uint16_t>(tenths < 0 ? tenths + 3600 : tenths);
}

std::uint16_t ModbusSensorBusDevice::sonar_register(std::size_t sonar) {
  const geometry::Pose2D pose = geometry::compose(world_.base_pose(), options_.sonar_poses[sonar]);
  const int rays = options_.sonar_rays;
  std::optional<double> nearest_m;
  for (int ray = 0; ray < rays; ++ray) {
    const double across = rays == 1 ? 0.0 : static_cast<double>(ray) / (rays - 1) - 0.5;
    const std::optional<double> range_m =
        world_.cast_ray({pose.x, pose.y}, pose.theta + across * options_.sonar_cone_rad,
                        options_.sonar_height_m, options_.sonar_max_m);
    if (range_m && (!nearest_m || *range_m < *nearest_m)) nearest_m = range_m;
  }
  if (!nearest_m) return 0;
  double range_m = *nearest_m;
  if (options_.sonar_noise_fraction > 0.0) {
    range_m *= 1.0 + std::normal_distribution<double>(0.0, options_.sonar_noise_fraction)(rng_);
  }
  if (range_m > options_.sonar_max_m) return 0;
  range_m = std::max(range_m, options_.sonar_min_m);
  return static_cast<std::uint16_t>(std::lround(range_m * 1000.0));
}

void ModbusSensorBusDevice::queue_reply(std::vector<std::uint8_t> reply, double now_s) {
  // Half duplex: a reply waits for the line as well as for the silence after the request.
  const double start_s = std::max(now_s + reply_delay_s_, line_free_s_);
  for (std::size_t i = 0; i < reply.size(); ++i) {
    outgoing_.push_back({start_s + static_cast<double>(i + 1) * byte_s_, reply[i]});
  }
  line_free_s_ = outgoing_.back().due_s;
}

}  // namespace mobot::emulate
