#include "drivers/protocol/pololu_maestro.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace mobot::protocol::maestro {
namespace {

constexpr std::uint8_t kDataMask = 0x7F;
constexpr std::size_t kMaxMultipleTargets = kChannels;
// A whole number of units computed through a calibration may come out a hair below itself.
constexpr double kRoundingSlack = 1e-9;

bool is_command_byte(std::uint8_t byte) { return (byte & 0x80u) != 0; }

void append_14bit(Packet& packet, std::uint16_t value) {
  value = std::min(value, kMax14Bit);
  packet.push_back(static_cast<std::uint8_t>(value & kDataMask));
  packet.push_back(static_cast<std::uint8_t>((value >> 7) & kDataMask));
}

std::uint16_t read_14bit(std::uint8_t low, std::uint8_t high) {
  return static_cast<std::uint16_t>((low & kDataMask) | ((high & kDataMask) << 7));
}

Packet channel_value(Command command, std::uint8_t channel, std::uint16_t value) {
  Packet packet{static_cast<std::uint8_t>(command), static_cast<std::uint8_t>(channel & kDataMask)};
  append_14bit(packet, value);
  return packet;
}

bool known_command(std::uint8_t byte) {
  switch (static_cast<Command>(byte)) {
    case Command::kSetTarget:
    case Command::kSetSpeed:
    case Command::kSetAcceleration:
    case Command::kGetPosition:
    case Command::kGetMovingState:
    case Command::kSetMultipleTargets:
    case Command::kGetErrors:
    case Command::kGoHome:
      return true;
  }
  return false;
}

// The data bytes the command in `so_far` (its command byte first) takes: Set Multiple Targets'
// follow from its count, the others are fixed. Nothing while the count is still to come.
std::optional<std::size_t> data_bytes(std::span<const std::uint8_t> so_far) {
  switch (static_cast<Command>(so_far.front())) {
    case Command::kSetTarget:
    case Command::kSetSpeed:
    case Command::kSetAcceleration:
      return 3;
    case Command::kGetPosition:
      return 1;
    case Command::kGetMovingState:
    case Command::kGetErrors:
    case Command::kGoHome:
      return 0;
    case Command::kSetMultipleTargets:
      if (so_far.size() < 2) return std::nullopt;
      return 2 + 2 * static_cast<std::size_t>(so_far[1]);
  }
  return 0;
}

ParsedCommand decode(std::span<const std::uint8_t> bytes) {
  ParsedCommand parsed;
  parsed.command = static_cast<Command>(bytes.front());
  switch (parsed.command) {
    case Command::kSetTarget:
    case Command::kSetSpeed:
    case Command::kSetAcceleration:
      parsed.channel = bytes[1];
      parsed.value = read_14bit(bytes[2], bytes[3]);
      break;
    case Command::kGetPosition:
      parsed.channel = bytes[1];
      break;
    case Command::kSetMultipleTargets:
      parsed.channel = bytes[2];
      for (std::size_t i = 3; i + 1 < bytes.size(); i += 2) {
        parsed.targets.push_back(read_14bit(bytes[i], bytes[i + 1]));
      }
      break;
    case Command::kGetMovingState:
    case Command::kGetErrors:
    case Command::kGoHome:
      break;
  }
  return parsed;
}

}  // namespace

std::string error_names(std::uint16_t errors) {
  static constexpr std::array<const char*, 9> kNames{
      "serial_signal", "serial_overrun",    "serial_rx_buffer_full",
      "serial_crc",    "serial_protocol",   "serial_timeout",
      "script_stack",  "script_call_stack", "script_program_counter"};
  std::string out;
  for (std::size_t bit = 0; bit < 16; ++bit) {
    if ((errors & (1u << bit)) == 0) continue;
    if (!out.empty()) out += '|';
    out += bit < kNames.size() ? kNames[bit] : "bit" + std::to_string(bit);
  }
  return out.empty() ? "none" : out;
}

std::uint8_t crc7(std::span<const std::uint8_t> bytes) {
  std::uint8_t crc = 0;
  for (std::uint8_t byte : bytes) {
    crc ^= byte;
    for (int bit = 0; bit < 8; ++bit) {
      if (crc & 1u) crc ^= kCrc7Polynomial;
      crc >>= 1;
    }
  }
  return crc;
}

Packet with_crc(Packet command) {
  command.push_back(crc7(command));
  return command;
}

Packet set_target(std::uint8_t channel, std::uint16_t target_qus) {
  return channel_value(Command::kSetTarget, channel, target_qus);
}

Packet set_speed(std::uint8_t channel, std::uint16_t speed) {
  return channel_value(Command::kSetSpeed, channel, speed);
}

Packet set_acceleration(std::uint8_t channel, std::uint16_t acceleration) {
  return channel_value(Command::kSetAcceleration, channel, acceleration);
}

Packet set_multiple_targets(std::uint8_t first_channel,
                            std::span<const std::uint16_t> targets_qus) {
  const std::size_t count = std::min(targets_qus.size(), kMaxMultipleTargets);
  Packet packet{static_cast<std::uint8_t>(Command::kSetMultipleTargets),
                static_cast<std::uint8_t>(count),
                static_cast<std::uint8_t>(first_channel & kDataMask)};
  for (std::size_t i = 0; i < count; ++i) append_14bit(packet, targets_qus[i]);
  return packet;
}

Packet get_position(std::uint8_t channel) {
  return {static_cast<std::uint8_t>(Command::kGetPosition),
          static_cast<std::uint8_t>(channel & kDataMask)};
}

Packet get_moving_state() { return {static_cast<std::uint8_t>(Command::kGetMovingState)}; }
Packet get_errors() { return {static_cast<std::uint8_t>(Command::kGetErrors)}; }
Packet go_home() { return {static_cast<std::uint8_t>(Command::kGoHome)}; }

std::optional<CommandEvent> CommandParser::feed(std::uint8_t byte) {
  if (is_command_byte(byte)) {
    // An unfinished command is dropped by the next command byte: a protocol error, and the new
    // command starts.
    const bool interrupted = !partial_.empty();
    partial_.clear();
    if (!known_command(byte)) return CommandEvent{std::nullopt, error_bit::kSerialProtocol};
    partial_.push_back(byte);
    if (!interrupted) return complete();
    // A command without data bytes completes at once, interruption or not.
    std::optional<CommandEvent> event = complete();
    if (!event) event.emplace();
    event->errors |= error_bit::kSerialProtocol;
    return event;
  } else {
    if (partial_.empty()) return CommandEvent{std::nullopt, error_bit::kSerialProtocol};
    partial_.push_back(byte);
  }
  return complete();
}

std::optional<CommandEvent> CommandParser::complete() {
  const std::optional<std::size_t> data = data_bytes(partial_);
  if (!data) return std::nullopt;
  if (static_cast<Command>(partial_.front()) == Command::kSetMultipleTargets &&
      (partial_[1] == 0 || partial_[1] > kMaxMultipleTargets)) {
    partial_.clear();
    return CommandEvent{std::nullopt, error_bit::kSerialProtocol};
  }
  const std::size_t length = 1 + *data + (crc_ ? 1 : 0);
  if (partial_.size() < length) return std::nullopt;
  Packet bytes;
  bytes.swap(partial_);
  if (crc_) {
    const std::uint8_t received = bytes.back();
    bytes.pop_back();
    if (crc7(bytes) != received) return CommandEvent{std::nullopt, error_bit::kSerialCrc};
  }
  return CommandEvent{decode(bytes), 0};
}

std::size_t reply_bytes(Query query) {
  switch (query) {
    case Query::kPosition:
    case Query::kErrors:
      return 2;
    case Query::kMovingState:
      return 1;
  }
  return 0;
}

std::size_t reply_bytes(std::span<const Query> queries) {
  std::size_t bytes = 0;
  for (Query query : queries) bytes += reply_bytes(query);
  return bytes;
}

std::optional<std::vector<std::uint16_t>> decode_replies(std::span<const Query> queries,
                                                         std::span<const std::uint8_t> bytes) {
  if (bytes.size() != reply_bytes(queries)) return std::nullopt;
  std::vector<std::uint16_t> values;
  values.reserve(queries.size());
  std::size_t offset = 0;
  for (Query query : queries) {
    if (reply_bytes(query) == 2) {
      values.push_back(static_cast<std::uint16_t>(bytes[offset] | (bytes[offset + 1] << 8)));
    } else {
      values.push_back(bytes[offset]);
    }
    offset += reply_bytes(query);
  }
  return values;
}

void ReplyCollector::expect(std::vector<Query> queries) {
  cancel();
  queries_ = std::move(queries);
  needed_ = reply_bytes(queries_);
  state_ = State::kWaiting;
  if (needed_ == 0) {
    state_ = State::kComplete;
    ++counters_.batches;
  }
}

void ReplyCollector::cancel() {
  if (state_ == State::kWaiting) ++counters_.abandoned;
  bytes_.clear();
  state_ = State::kIdle;
}

ReplyCollector::State ReplyCollector::feed(std::span<const std::uint8_t> bytes) {
  counters_.bytes += bytes.size();
  if (state_ == State::kWaiting) {
    // The same whatever the chunks: the answers complete at their last byte, and what follows
    // them overruns.
    const std::size_t taken = std::min(needed_ - bytes_.size(), bytes.size());
    bytes_.insert(bytes_.end(), bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(taken));
    bytes = bytes.subspan(taken);
    if (bytes_.size() == needed_) {
      ++counters_.batches;
      state_ = State::kComplete;
    }
  }
  if (bytes.empty()) return state_;
  // Nothing was asked for these: whatever came before can no longer be trusted either.
  if (state_ != State::kOverrun) ++counters_.overruns;
  state_ = State::kOverrun;
  bytes_.clear();
  return state_;
}

std::optional<std::vector<std::uint16_t>> ReplyCollector::values() const {
  if (state_ != State::kComplete) return std::nullopt;
  return decode_replies(queries_, bytes_);
}

bool plausible_servo_position(std::uint16_t position_qus) {
  return position_qus == 0 || (position_qus >= kMinPulse_us * kQuarterUsPerUs &&
                               position_qus <= kMaxPulse_us * kQuarterUsPerUs);
}

bool plausible_analog(std::uint16_t value) { return value <= kAnalogFullScale; }

bool plausible_errors(std::uint16_t errors) { return (errors & ~error_bit::kDefined) == 0; }

bool plausible_moving_state(std::uint16_t state) { return state <= 1; }

double pulse_us_for_angle(const ServoCalibration& servo, double angle_rad) {
  return servo.centre_us + servo.sign * servo.us_per_rad * angle_rad;
}

std::uint16_t target_for_angle(const ServoCalibration& servo, double angle_rad) {
  double pulse_us = pulse_us_for_angle(servo, angle_rad);
  if (!std::isfinite(pulse_us)) pulse_us = servo.centre_us;
  const double qus = std::round(pulse_us * kQuarterUsPerUs);
  return static_cast<std::uint16_t>(std::clamp(qus, 1.0, static_cast<double>(kMax14Bit)));
}

std::optional<double> angle_for_position(const ServoCalibration& servo,
                                         std::uint16_t position_qus) {
  if (position_qus == 0 || !(servo.us_per_rad > 0.0)) return std::nullopt;
  const double pulse_us = static_cast<double>(position_qus) / kQuarterUsPerUs;
  return (pulse_us - servo.centre_us) / (servo.sign * servo.us_per_rad);
}

std::uint16_t speed_for_rate(const ServoCalibration& servo, double rate_rad_s) {
  const double units = rate_rad_s * servo.us_per_rad * kQuarterUsPerUs * kSpeedPeriod_s;
  if (!(units > 0.0) || !std::isfinite(units)) return 0;
  return static_cast<std::uint16_t>(
      std::clamp(std::floor(units + kRoundingSlack), 1.0, double{kMax14Bit}));
}

double rate_for_speed(const ServoCalibration& servo, std::uint16_t speed) {
  if (speed == 0) return std::numeric_limits<double>::infinity();
  return speed / (servo.us_per_rad * kQuarterUsPerUs * kSpeedPeriod_s);
}

std::uint16_t acceleration_for(const ServoCalibration& servo, double accel_rad_s2) {
  const double units =
      accel_rad_s2 * servo.us_per_rad * kQuarterUsPerUs * kSpeedPeriod_s * kAccelerationPeriod_s;
  if (!(units > 0.0) || !std::isfinite(units)) return 0;
  return static_cast<std::uint16_t>(
      std::clamp(std::floor(units + kRoundingSlack), 1.0, static_cast<double>(kMaxAcceleration)));
}

double analog_volts(std::uint16_t value) {
  return static_cast<double>(value) * kAnalogFullScaleV / kAnalogFullScale;
}

std::optional<double> range_from_analog(std::uint16_t value, const RangerScale& scale) {
  if (!plausible_analog(value)) return std::nullopt;
  const double range_m = analog_volts(value) * scale.m_per_volt;
  if (!(range_m < scale.max_range_m)) return std::nullopt;
  return range_m;
}

}  // namespace mobot::protocol::maestro
