#include "drivers/protocol/motion_mind.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace mobot::protocol::motion_mind {
namespace {

constexpr std::int64_t kI32Min = std::numeric_limits<std::int32_t>::min();
constexpr std::int64_t kI32Max = std::numeric_limits<std::int32_t>::max();
constexpr std::int64_t kU32Max = std::numeric_limits<std::uint32_t>::max();

// Figure 18 of the data sheet.
constexpr std::array<RegisterInfo, kRegisterCount> kRegisters = {{
    {"POSITION", 4, true, true, kI32Min, kI32Max, 0},
    {"VELOCITYLIMIT", 2, false, true, 1, 1023, 1023},
    {"VELOCITYFF", 1, false, true, 0, 255, 128},
    {"FUNCTION", 2, false, true, 0, 65535, 0},
    {"PTERM", 2, false, true, 0, 65535, 6000},
    {"ITERM", 2, false, true, 0, 65535, 35},
    {"DTERM", 2, false, true, 0, 65535, 0},
    {"ADDRESS", 1, false, true, 0, 255, 1},
    {"PIDSCALAR", 1, false, true, 0, 32, 14},
    {"TIMER", 1, false, true, 1, 255, 10},
    {"RCMAX", 2, false, true, 0, 65535, 1152},
    {"RCMIN", 2, false, true, 0, 65535, 576},
    {"RCBAND", 2, false, true, 0, 65535, 15},
    {"RCCOUNT", 2, false, false, 0, 65535, 0},
    {"VELOCITY", 2, true, false, -32768, 32767, 0},
    {"TIME", 4, false, false, 0, kU32Max, 0},
    {"STATUS", 2, false, false, 0, 65535, 0},
    {"REVISION", 1, false, false, 0, 255, 0},
    {"MODE", 1, false, false, 0, 7, 0},
    {"ANALOGCON", 2, false, false, 0, 1023, 0},
    {"ANALOGFBCK", 2, false, false, 0, 1023, 0},
    {"PWMOUT", 2, true, false, -1023, 1023, 0},
    {"INDEXPOS", 4, true, false, kI32Min, kI32Max, 0},
    {"VNLIMIT", 4, true, true, kI32Min, kI32Max, -100000},
    {"VPLIMIT", 4, true, true, kI32Min, kI32Max, 100000},
    {"PWMLIMIT", 2, false, true, 1, 1023, 1023},
    {"DEADBAND", 2, false, true, 0, 1023, 15},
    {"DESIREDPOSITION", 4, true, false, kI32Min, kI32Max, 0},
    {"AMPSLIMIT", 2, false, true, 0, 1023, 512},
    {"AMPS", 2, false, false, 0, 1023, 0},
    {"FUNCTION2", 2, false, true, 0, 65535, 0},
    {"THERMISTOR", 2, false, false, 0, 1023, 0},
}};

constexpr std::uint8_t kFirstCommand = static_cast<std::uint8_t>(Command::kChangeSpeed);
constexpr std::uint8_t kLastCommand = static_cast<std::uint8_t>(Command::kReadRegister);

void append_le(Packet& packet, std::int64_t value, std::size_t size_bytes) {
  const auto bits = static_cast<std::uint64_t>(value);
  for (std::size_t i = 0; i < size_bytes; ++i) {
    packet.push_back(static_cast<std::uint8_t>((bits >> (8 * i)) & 0xFFu));
  }
}

std::int64_t read_le(std::span<const std::uint8_t> bytes, bool is_signed) {
  std::uint64_t bits = 0;
  for (std::size_t i = bytes.size(); i-- > 0;) bits = (bits << 8) | bytes[i];
  if (is_signed && !bytes.empty() && bytes.size() < 8) {
    const std::uint64_t sign = std::uint64_t{1} << (8 * bytes.size() - 1);
    if ((bits & sign) != 0) bits |= ~((sign << 1) - 1);
  }
  return static_cast<std::int64_t>(bits);
}

Packet finish(Packet packet) {
  packet.push_back(checksum(packet));
  return packet;
}

Packet command_with(Command command, std::uint8_t address, std::int64_t value,
                    std::size_t size_bytes) {
  Packet packet{static_cast<std::uint8_t>(command), address};
  append_le(packet, value, size_bytes);
  return finish(std::move(packet));
}

Packet write_command(Command command, std::uint8_t address, Register reg, std::int64_t value) {
  const RegisterInfo& info = register_info(reg);
  if (info.writable) value = std::clamp(value, info.min_value, info.max_value);
  Packet packet{static_cast<std::uint8_t>(command), address, static_cast<std::uint8_t>(reg)};
  append_le(packet, value, info.size_bytes);
  return finish(std::move(packet));
}

}  // namespace

const RegisterInfo& register_info(Register reg) {
  return kRegisters[static_cast<std::size_t>(reg) % kRegisterCount];
}

std::optional<Register> register_from_index(std::uint8_t index) {
  if (index >= kRegisterCount) return std::nullopt;
  return static_cast<Register>(index);
}

std::size_t read_data_bytes(RegisterMask mask) {
  std::size_t bytes = 0;
  for (std::size_t i = 0; i < kRegisterCount; ++i) {
    if ((mask >> i) & 1u) bytes += kRegisters[i].size_bytes;
  }
  return bytes;
}

std::size_t motion_data_bytes(std::uint16_t function_register) {
  std::size_t bytes = 0;
  if (function_register & function_bit::kRetPos) bytes += 4;
  if (function_register & function_bit::kRetVel) bytes += 2;
  if (function_register & function_bit::kRetTime) bytes += 4;
  return bytes;
}

std::uint8_t checksum(std::span<const std::uint8_t> bytes) {
  unsigned sum = 0;
  for (std::uint8_t byte : bytes) sum += byte;
  return static_cast<std::uint8_t>(sum & 0xFFu);
}

Packet change_speed(std::uint8_t address, int pwm_duty) {
  return command_with(Command::kChangeSpeed, address, std::clamp(pwm_duty, -1023, 1023), 2);
}

Packet move_to_absolute(std::uint8_t address, std::int32_t position_counts) {
  return command_with(Command::kMoveToAbsolute, address, position_counts, 4);
}

Packet move_to_relative(std::uint8_t address, std::int32_t offset_counts) {
  return command_with(Command::kMoveToRelative, address, offset_counts, 4);
}

Packet move_at_velocity(std::uint8_t address, int counts_per_period) {
  return command_with(Command::kMoveAtVelocity, address,
                      std::clamp(counts_per_period, -32768, 32767), 2);
}

Packet write_register(std::uint8_t address, Register reg, std::int64_t value) {
  return write_command(Command::kWrite, address, reg, value);
}

Packet write_store_register(std::uint8_t address, Register reg, std::int64_t value) {
  return write_command(Command::kWriteStore, address, reg, value);
}

Packet read_registers(std::uint8_t address, RegisterMask mask) {
  return command_with(Command::kRead, address, mask, 4);
}

Packet read_register(std::uint8_t address, Register reg) {
  return finish(
      {static_cast<std::uint8_t>(Command::kReadRegister), address, static_cast<std::uint8_t>(reg)});
}

Packet restore_defaults(std::uint8_t address) {
  return finish({static_cast<std::uint8_t>(Command::kRestore), address});
}

Packet reset(std::uint8_t address) {
  return finish({static_cast<std::uint8_t>(Command::kReset), address});
}

std::optional<ParsedCommand> parse_command(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 3 || bytes[0] < kFirstCommand || bytes[0] > kLastCommand) {
    return std::nullopt;
  }
  ParsedCommand parsed;
  parsed.command = static_cast<Command>(bytes[0]);
  parsed.address = bytes[1];
  std::size_t data_offset = 2;
  std::size_t data_bytes = 0;
  bool data_signed = true;
  switch (parsed.command) {
    case Command::kChangeSpeed:
    case Command::kMoveAtVelocity:
      data_bytes = 2;
      break;
    case Command::kMoveToAbsolute:
    case Command::kMoveToRelative:
      data_bytes = 4;
      break;
    case Command::kRead:
      data_bytes = 4;
      data_signed = false;
      break;
    case Command::kRestore:
    case Command::kReset:
      break;
    case Command::kReadRegister:
    case Command::kWrite:
    case Command::kWriteStore: {
      const std::optional<Register> reg = register_from_index(bytes[2]);
      if (!reg) return std::nullopt;
      parsed.reg = *reg;
      data_offset = 3;
      if (parsed.command != Command::kReadRegister) {
        data_bytes = register_info(*reg).size_bytes;
        data_signed = register_info(*reg).is_signed;
      }
      break;
    }
  }
  const std::size_t length = data_offset + data_bytes + 1;
  if (bytes.size() != length || checksum(bytes.first(length - 1)) != bytes[length - 1]) {
    return std::nullopt;
  }
  parsed.value = read_le(bytes.subspan(data_offset, data_bytes), data_signed);
  if (parsed.command == Command::kRead) parsed.mask = static_cast<RegisterMask>(parsed.value);
  return parsed;
}

ExpectedReply ack_reply() { return {}; }

ExpectedReply read_reply(std::uint8_t address, RegisterMask mask) {
  return {false, address, read_data_bytes(mask)};
}

ExpectedReply read_register_reply(std::uint8_t address, Register reg) {
  return {false, address, register_info(reg).size_bytes};
}

ExpectedReply motion_reply(std::uint8_t address, std::uint16_t function_register) {
  const std::size_t data_bytes = motion_data_bytes(function_register);
  if (data_bytes == 0) return ack_reply();
  return {false, address, data_bytes};
}

std::size_t reply_bytes(const ExpectedReply& expected) {
  return expected.ack ? 1 : expected.data_bytes + 2;
}

Packet encode_data_reply(std::uint8_t address, std::span<const std::uint8_t> data) {
  Packet packet{address};
  packet.insert(packet.end(), data.begin(), data.end());
  return finish(std::move(packet));
}

std::optional<std::int64_t> register_value(RegisterMask mask, Register reg,
                                           std::span<const std::uint8_t> data) {
  if ((mask & mask_of(reg)) == 0) return std::nullopt;
  const RegisterMask before = mask & (mask_of(reg) - 1);
  const std::size_t offset = read_data_bytes(before);
  const RegisterInfo& info = register_info(reg);
  if (offset + info.size_bytes > data.size()) return std::nullopt;
  return read_le(data.subspan(offset, info.size_bytes), info.is_signed);
}

std::optional<MotionFeedback> decode_motion_reply(std::uint16_t function_register,
                                                  std::span<const std::uint8_t> data) {
  if (data.size() != motion_data_bytes(function_register)) return std::nullopt;
  MotionFeedback feedback;
  std::size_t offset = 0;
  if (function_register & function_bit::kRetPos) {
    feedback.position_counts = static_cast<std::int32_t>(read_le(data.subspan(offset, 4), true));
    offset += 4;
  }
  if (function_register & function_bit::kRetVel) {
    feedback.velocity_counts_per_period =
        static_cast<std::int16_t>(read_le(data.subspan(offset, 2), true));
    offset += 2;
  }
  if (function_register & function_bit::kRetTime) {
    feedback.time_periods = static_cast<std::uint32_t>(read_le(data.subspan(offset, 4), false));
  }
  return feedback;
}

void ReplyParser::expect(const ExpectedReply& expected) {
  cancel();
  expected_ = expected;
}

void ReplyParser::cancel() {
  if (expected_) ++counters_.abandoned;
  counters_.discarded_bytes += partial_.size();
  partial_.clear();
  expected_.reset();
}

std::optional<Reply> ReplyParser::feed(std::span<const std::uint8_t> bytes) {
  std::optional<Reply> reply;
  for (std::uint8_t byte : bytes) {
    ++counters_.bytes;
    std::optional<Reply> taken = take(byte);
    if (taken) reply = std::move(taken);
  }
  return reply;
}

std::optional<Reply> ReplyParser::take(std::uint8_t byte) {
  if (!expected_) {
    ++counters_.discarded_bytes;
    return std::nullopt;
  }
  if (expected_->ack) {
    if (byte != kAck) {
      ++counters_.discarded_bytes;
      return std::nullopt;
    }
    ++counters_.replies;
    expected_.reset();
    return Reply{true, 0, {}};
  }
  if (partial_.empty() && byte != expected_->address) {
    ++counters_.discarded_bytes;
    return std::nullopt;
  }
  partial_.push_back(byte);
  if (partial_.size() < expected_->data_bytes + 2) return std::nullopt;
  const std::span<const std::uint8_t> frame(partial_);
  if (checksum(frame.first(frame.size() - 1)) != frame.back()) {
    ++counters_.checksum_errors;
    resync();
    return std::nullopt;
  }
  Reply reply{false, partial_.front(), {partial_.begin() + 1, partial_.end() - 1}};
  ++counters_.replies;
  partial_.clear();
  expected_.reset();
  return reply;
}

void ReplyParser::resync() {
  auto start = std::find(partial_.begin() + 1, partial_.end(), expected_->address);
  counters_.discarded_bytes += static_cast<std::uint64_t>(start - partial_.begin());
  partial_.erase(partial_.begin(), start);
}

Status decode_status(std::uint16_t status_register) {
  auto bit = [status_register](std::uint16_t mask) { return (status_register & mask) != 0; };
  Status status;
  status.negative_limit = bit(status_bit::kNegativeLimit);
  status.positive_limit = bit(status_bit::kPositiveLimit);
  status.brake = bit(status_bit::kBrake);
  status.index = bit(status_bit::kIndex);
  status.virtual_negative_limit = bit(status_bit::kVirtualNegativeLimit);
  status.virtual_positive_limit = bit(status_bit::kVirtualPositiveLimit);
  status.current_limit = bit(status_bit::kCurrentLimit);
  status.pwm_limit = bit(status_bit::kPwmLimit);
  status.in_position = bit(status_bit::kInPosition);
  status.temperature_fault = bit(status_bit::kTemperatureFault);
  return status;
}

double counts_per_period_per_radps(double counts_per_rev) {
  return counts_per_rev * kPidPeriod_s / (2.0 * std::numbers::pi);
}

int velocity_setpoint(double radps, double counts_per_rev) {
  const double exact = radps * counts_per_period_per_radps(counts_per_rev);
  if (!std::isfinite(exact)) return 0;
  return static_cast<int>(std::lround(std::clamp(exact, -32768.0, 32767.0)));
}

double setpoint_radps(double counts_per_period, double counts_per_rev) {
  const double per_radps = counts_per_period_per_radps(counts_per_rev);
  if (!(per_radps > 0.0) || !std::isfinite(per_radps)) return 0.0;
  return counts_per_period / per_radps;
}

int SetpointDither::next(double radps, double counts_per_rev) {
  const double exact = radps * counts_per_period_per_radps(counts_per_rev) + residual_;
  // A stop must be an exact 0, not a remainder's last unit.
  if (radps == 0.0 || !std::isfinite(exact)) {
    residual_ = 0.0;
    return 0;
  }
  const int setpoint = static_cast<int>(std::lround(std::clamp(exact, -32768.0, 32767.0)));
  residual_ = std::clamp(exact - setpoint, -1.0, 1.0);
  return setpoint;
}

std::int64_t PositionUnwrap::update(std::int32_t raw_counts) {
  if (!started_) {
    started_ = true;
    total_ = raw_counts;
  } else {
    const auto delta = static_cast<std::int32_t>(static_cast<std::uint32_t>(raw_counts) -
                                                 static_cast<std::uint32_t>(last_raw_));
    total_ += delta;
  }
  last_raw_ = raw_counts;
  return total_;
}

double thermistor_celsius(int thermistor_register) { return (thermistor_register - 1104) * -0.165; }

double amps_register_amperes(int amps_register) { return amps_register * 0.02; }

double wire_time_s(std::size_t bytes, int baud) {
  if (baud <= 0) return std::numeric_limits<double>::infinity();
  return static_cast<double>(bytes) * 10.0 / baud;
}

double max_round_trip_s(std::size_t command_bytes, std::size_t reply_bytes, int baud,
                        bool write_store) {
  return wire_time_s(command_bytes, baud) + kEndOfCommandGap_s +
         (write_store ? kMaxWriteStoreResponseDelay_s : kMaxResponseDelay_s) +
         wire_time_s(reply_bytes, baud);
}

BoardSetup r1_wheel_setup() { return BoardSetup{}; }

BoardSetup r1_tilt_setup() {
  BoardSetup setup;
  setup.d_term = 2;
  return setup;
}

std::vector<Exchange> setup_exchanges(std::uint8_t address, const BoardSetup& setup) {
  std::vector<Exchange> exchanges;
  auto write = [&](Register reg, std::int64_t value) {
    exchanges.push_back({write_register(address, reg, value), ack_reply()});
  };
  write(Register::kPTerm, setup.p_term);
  write(Register::kITerm, setup.i_term);
  write(Register::kDTerm, setup.d_term);
  if (setup.pid_scalar) write(Register::kPidScalar, *setup.pid_scalar);
  if (setup.amps_limit) write(Register::kAmpsLimit, *setup.amps_limit);
  if (setup.pwm_limit) write(Register::kPwmLimit, *setup.pwm_limit);
  if (setup.timer_periods) write(Register::kTimer, *setup.timer_periods);
  write(Register::kFunction, setup.function);
  return exchanges;
}

}  // namespace mobot::protocol::motion_mind
