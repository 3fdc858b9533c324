#include "tools/emulate/devices/motion_mind_device.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/geometry/pose2d.h"
#include "core/numeric/finite.h"

namespace mobot::emulate {
namespace mm = protocol::motion_mind;

namespace {

constexpr double kPeriod_s = mm::kPidPeriod_s;
// Past this, a gap between calls is jumped instead of run period by period.
constexpr double kMaxRunGap_s = 60.0;
// Later times count as this one (31 years), which keeps every count well inside 64 bits.
constexpr double kLastTime_s = 1e9;
constexpr std::size_t kVelocityWindow = 64;
constexpr std::int64_t kRevision = 5;
constexpr std::int64_t kSerialPidMode = 4;
// THERMISTOR at 25 C by the data sheet's C = (THERMISTOR - 1104) x -0.165.
constexpr std::int64_t kThermistorAt25C = 952;

std::size_t index_of(mm::Register reg) { return static_cast<std::size_t>(reg); }

std::int32_t wrap32(std::int64_t value) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(static_cast<std::uint64_t>(value)));
}

void append_le(std::vector<std::uint8_t>& out, std::int64_t value, std::size_t size_bytes) {
  const auto bits = static_cast<std::uint64_t>(value);
  for (std::size_t i = 0; i < size_bytes; ++i) {
    out.push_back(static_cast<std::uint8_t>((bits >> (8 * i)) & 0xFFu));
  }
}

std::array<std::int64_t, mm::kRegisterCount> factory_defaults() {
  std::array<std::int64_t, mm::kRegisterCount> registers{};
  for (std::size_t i = 0; i < mm::kRegisterCount; ++i) {
    registers[i] = mm::register_info(static_cast<mm::Register>(i)).default_value;
  }
  return registers;
}

}  // namespace

// One board: its registers, EEPROM and the shaft it drives.
class MotionMindBus::Board {
 public:
  explicit Board(const MotionMindBoardOptions& options)
      : options_(options), registers_(factory_defaults()), eeprom_(registers_) {
    registers_[index_of(mm::Register::kAddress)] = options.address;
    eeprom_ = registers_;
    position_offset_ = options.initial_position_counts;
    alpha_ = options.speed_time_constant_s > 0.0
                 ? 1.0 - std::exp(-kPeriod_s / options.speed_time_constant_s)
                 : 1.0;
    update_switch(true);
  }

  const MotionMindBoardOptions& options() const { return options_; }
  std::uint8_t address() const {
    return static_cast<std::uint8_t>(registers_[index_of(mm::Register::kAddress)]);
  }
  double shaft_angle_rad() const {
    return travel_counts_ / options_.counts_per_rev * 2.0 * std::numbers::pi;
  }
  double shaft_speed_radps() const {
    return mm::setpoint_radps(speed_counts_per_period_, options_.counts_per_rev);
  }
  std::optional<double> tilt_pitch_deg() const {
    if (!options_.tilt) return std::nullopt;
    return options_.tilt->start_pitch_deg + travel_counts_ / options_.tilt->counts_per_degree;
  }
  std::int64_t position() const {
    return static_cast<std::int64_t>(std::floor(travel_counts_)) + position_offset_;
  }

  // One PID period.
  void step(std::mt19937_64& rng) {
    double target = target_counts_per_period();
    const double max_speed = options_.max_counts_per_period;
    target = std::clamp(target, -max_speed, max_speed);
    // The board will not drive into a closed limit switch.
    const bool negative_blocked = (status_inputs_ & mm::status_bit::kNegativeLimit) != 0;
    if (negative_blocked) {
      target = std::max(target, 0.0);
      speed_counts_per_period_ = std::max(speed_counts_per_period_, 0.0);
    }
    speed_counts_per_period_ += (target - speed_counts_per_period_) * alpha_;
    std::normal_distribution<double> unit(0.0, 1.0);
    const double noise = options_.speed_noise_fraction * std::abs(speed_counts_per_period_);
    double travel = speed_counts_per_period_;
    if (noise > 0.0) travel += noise * unit(rng);
    if (negative_blocked) travel = std::max(travel, 0.0);
    const double before = std::floor(travel_counts_);
    travel_counts_ += travel;
    velocity_window_[window_next_] = static_cast<std::int64_t>(std::floor(travel_counts_) - before);
    window_next_ = (window_next_ + 1) % kVelocityWindow;
    ++time_periods_;
    update_switch(false);
  }

  // Long gaps: the shaft is taken to where its target leads, without noise or window updates.
  void jump(std::uint64_t periods) {
    time_periods_ += periods;
    if (position_mode_) {
      travel_counts_ += static_cast<double>(target_position_ - position());
      speed_counts_per_period_ = 0.0;
    } else {
      const double max_speed = options_.max_counts_per_period;
      speed_counts_per_period_ = std::clamp(target_counts_per_period(), -max_speed, max_speed);
      travel_counts_ += speed_counts_per_period_ * static_cast<double>(periods);
    }
    if (options_.tilt && speed_counts_per_period_ <= 0.0 &&
        *tilt_pitch_deg() < options_.tilt->lower_limit_deg) {
      // It would have stopped at the switch.
      travel_counts_ = (options_.tilt->lower_limit_deg - options_.tilt->start_pitch_deg) *
                       options_.tilt->counts_per_degree;
      speed_counts_per_period_ = 0.0;
    }
    update_switch(true);
  }

  struct Answer {
    std::optional<mm::Packet> reply;
    bool slow = false;  // WRITE_STORE: the EEPROM write delays the answer
  };

  Answer apply(const mm::ParsedCommand& command) {
    Answer answer;
    switch (command.command) {
      case mm::Command::kChangeSpeed:
        // Open-loop mode only: in mode 4 the command is not taken.
        return answer;
      case mm::Command::kMoveToAbsolute:
        position_mode_ = true;
        target_position_ = command.value;
        answer.reply = motion_reply();
        return answer;
      case mm::Command::kMoveToRelative:
        position_mode_ = true;
        target_position_ = position() + command.value;
        answer.reply = motion_reply();
        return answer;
      case mm::Command::kMoveAtVelocity:
        position_mode_ = false;
        target_velocity_ = static_cast<double>(command.value);
        answer.reply = motion_reply();
        return answer;
      case mm::Command::kWrite:
      case mm::Command::kWriteStore:
        write(command.reg, command.value, command.command == mm::Command::kWriteStore);
        answer.reply = mm::Packet{mm::kAck};
        answer.slow = command.command == mm::Command::kWriteStore;
        return answer;
      case mm::Command::kRead: {
        std::vector<std::uint8_t> data;
        for (std::size_t i = 0; i < mm::kRegisterCount; ++i) {
          if ((command.mask >> i) & 1u) append_register(data, static_cast<mm::Register>(i));
        }
        answer.reply = mm::encode_data_reply(address(), data);
        return answer;
      }
      case mm::Command::kReadRegister: {
        std::vector<std::uint8_t> data;
        append_register(data, command.reg);
        answer.reply = mm::encode_data_reply(address(), data);
        return answer;
      }
      case mm::Command::kRestore:
        registers_ = factory_defaults();
        eeprom_ = registers_;
        stop();
        answer.reply = mm::Packet{mm::kAck};
        return answer;
      case mm::Command::kReset:
        registers_ = eeprom_;
        position_offset_ =
            ((registers_[index_of(mm::Register::kFunction)] & mm::function_bit::kPosPowerUp) != 0
                 ? eeprom_[index_of(mm::Register::kPosition)]
                 : 0) -
            static_cast<std::int64_t>(std::floor(travel_counts_));
        time_periods_ = 0;
        stop();
        answer.reply = mm::Packet{mm::kAck};
        return answer;
    }
    return answer;
  }

 private:
  double target_counts_per_period() const {
    const std::int64_t function = registers_[index_of(mm::Register::kFunction)];
    if (function & mm::function_bit::kDisablePid) return 0.0;
    if (!position_mode_) return target_velocity_;
    // A critically damped approach with the speed lag: the position gain is 1 / (4 tau).
    const double tau_s = std::max(options_.speed_time_constant_s, kPeriod_s);
    double target = static_cast<double>(target_position_ - position()) * kPeriod_s / (4.0 * tau_s);
    if (function & mm::function_bit::kVelLimit) {
      const double limit = static_cast<double>(registers_[index_of(mm::Register::kVelocityLimit)]);
      target = std::clamp(target, -limit, limit);
    }
    return target;
  }

  void stop() {
    position_mode_ = false;
    target_velocity_ = 0.0;
  }

  void write(mm::Register reg, std::int64_t value, bool store) {
    const mm::RegisterInfo& info = mm::register_info(reg);
    if (!info.writable) return;
    value = std::clamp(value, info.min_value, info.max_value);
    if (reg == mm::Register::kPosition) {
      position_offset_ = value - static_cast<std::int64_t>(std::floor(travel_counts_));
      if (position_mode_) target_position_ = value;
    }
    registers_[index_of(reg)] = value;
    if (store) {
      eeprom_[index_of(reg)] = value;
      // The board stops the motor before it writes its EEPROM.
      stop();
    }
  }

  std::int64_t status() const {
    std::int64_t bits = status_inputs_;
    if (position_mode_ &&
        std::abs(target_position_ - position()) <=
            ((registers_[index_of(mm::Register::kFunction)] & mm::function_bit::kEnableDeadband)
                 ? registers_[index_of(mm::Register::kDeadband)]
                 : 0)) {
      bits |= mm::status_bit::kInPosition;
    }
    return bits;
  }

  std::int64_t value(mm::Register reg) const {
    const double max_speed = options_.max_counts_per_period;
    switch (reg) {
      case mm::Register::kPosition:
        return wrap32(position());
      case mm::Register::kVelocity: {
        std::int64_t sum = 0;
        for (std::int64_t counts : velocity_window_) sum += counts;
        return std::clamp<std::int64_t>(sum / static_cast<std::int64_t>(kVelocityWindow), -32768,
                                        32767);
      }
      case mm::Register::kTime:
        return static_cast<std::int64_t>(time_periods_ & 0xFFFFFFFFu);
      case mm::Register::kStatus:
        return status();
      case mm::Register::kRevision:
        return kRevision;
      case mm::Register::kMode:
        return kSerialPidMode;
      case mm::Register::kPwmOut:
        return std::clamp<std::int64_t>(std::llround(speed_counts_per_period_ / max_speed * 1023.0),
                                        -1023, 1023);
      case mm::Register::kAmps:
        // A no-load draw plus a share for speed: enough for a plausible reading.
        return std::llround((0.3 + 1.5 * std::abs(speed_counts_per_period_) / max_speed) / 0.02);
      case mm::Register::kThermistor:
        return kThermistorAt25C;
      case mm::Register::kDesiredPosition:
        return wrap32(position_mode_ ? target_position_ : position());
      default:
        return registers_[index_of(reg)];
    }
  }

  void append_register(std::vector<std::uint8_t>& data, mm::Register reg) const {
    append_le(data, value(reg), mm::register_info(reg).size_bytes);
  }

  mm::Packet motion_reply() const {
    const auto function = static_cast<std::uint16_t>(registers_[index_of(mm::Register::kFunction)]);
    if (mm::motion_data_bytes(function) == 0) return mm::Packet{mm::kAck};
    std::vector<std::uint8_t> data;
    if (function & mm::function_bit::kRetPos) append_register(data, mm::Register::kPosition);
    if (function & mm::function_bit::kRetVel) append_register(data, mm::Register::kVelocity);
    if (function & mm::function_bit::kRetTime) append_register(data, mm::Register::kTime);
    return mm::encode_data_reply(address(), data);
  }

  // The switch input follows the pitch once it has held for TIMER periods (`settle`: at once).
  void update_switch(bool settle) {
    if (!options_.tilt) return;
    const bool closed = *tilt_pitch_deg() <= options_.tilt->lower_limit_deg;
    const bool shown = (status_inputs_ & mm::status_bit::kNegativeLimit) != 0;
    if (closed == shown) {
      switch_held_periods_ = 0;
      return;
    }
    ++switch_held_periods_;
    if (settle || switch_held_periods_ >= registers_[index_of(mm::Register::kTimer)]) {
      status_inputs_ ^= mm::status_bit::kNegativeLimit;
      switch_held_periods_ = 0;
    }
  }

  MotionMindBoardOptions options_;
  std::array<std::int64_t, mm::kRegisterCount> registers_;
  std::array<std::int64_t, mm::kRegisterCount> eeprom_;
  double alpha_ = 1.0;
  double travel_counts_ = 0.0;        // true shaft travel since power-up
  std::int64_t position_offset_ = 0;  // POSITION = floor(travel) + offset
  double speed_counts_per_period_ = 0.0;
  bool position_mode_ = false;
  double target_velocity_ = 0.0;
  std::int64_t target_position_ = 0;
  std::array<std::int64_t, kVelocityWindow> velocity_window_{};
  std::size_t window_next_ = 0;
  std::uint64_t time_periods_ = 0;
  std::int64_t status_inputs_ = 0;
  std::int64_t switch_held_periods_ = 0;
};

MotionMindBus::MotionMindBus(MotionMindBusOptions options)
    : options_(std::move(options)), rng_(options_.seed) {
  if (options_.baud <= 0 || !finite_positive(options_.end_of_command_gap_s) ||
      !finite_non_negative(options_.response_delay_s) ||
      !finite_non_negative(options_.write_store_delay_s)) {
    throw std::invalid_argument("MotionMindBus: bad baud rate, gap or delay");
  }
  for (const MotionMindBoardOptions& board : options_.boards) {
    const std::string which = "MotionMindBus: board " + std::to_string(board.address);
    if (!finite_positive(board.counts_per_rev) || !finite_positive(board.max_counts_per_period) ||
        !finite_non_negative(board.speed_time_constant_s) ||
        !finite_non_negative(board.speed_noise_fraction)) {
      throw std::invalid_argument(which + ": bad scale, speed, lag or noise");
    }
    if (board.tilt && (!finite_positive(board.tilt->counts_per_degree) ||
                       !std::isfinite(board.tilt->lower_limit_deg) ||
                       !std::isfinite(board.tilt->start_pitch_deg))) {
      throw std::invalid_argument(which + ": bad tilt axis");
    }
    if (find(board.address) != nullptr) throw std::invalid_argument(which + ": address taken");
    boards_.push_back(std::make_unique<Board>(board));
  }
}

MotionMindBus::~MotionMindBus() = default;

void MotionMindBus::receive(std::span<const std::uint8_t> bytes, double now_s) {
  advance(now_s);
  if (bytes.empty()) return;
  for (std::uint8_t byte : bytes) {
    if (rx_.size() < mm::kMaxCommandBytes) {
      rx_.push_back(byte);
    } else {
      rx_overflow_ = true;
    }
  }
  last_rx_s_ = now_s_;
}

std::vector<std::uint8_t> MotionMindBus::transmit(double now_s) {
  advance(now_s);
  std::vector<std::uint8_t> out;
  while (!tx_.empty() && tx_.front().release_s <= now_s_) {
    out.push_back(tx_.front().byte);
    tx_.pop_front();
  }
  return out;
}

std::optional<double> MotionMindBus::shaft_angle_rad(std::uint8_t address) const {
  const Board* board = find(address);
  if (board == nullptr) return std::nullopt;
  return board->shaft_angle_rad();
}

std::optional<double> MotionMindBus::shaft_speed_radps(std::uint8_t address) const {
  const Board* board = find(address);
  if (board == nullptr) return std::nullopt;
  return board->shaft_speed_radps();
}

std::optional<std::int32_t> MotionMindBus::position_register(std::uint8_t address) const {
  const Board* board = find(address);
  if (board == nullptr) return std::nullopt;
  return wrap32(board->position());
}

std::optional<double> MotionMindBus::tilt_pitch_deg(std::uint8_t address) const {
  const Board* board = find(address);
  if (board == nullptr) return std::nullopt;
  return board->tilt_pitch_deg();
}

void MotionMindBus::advance(double now_s) {
  // Time never runs backwards, and a time that is not a number does not move it.
  if (!std::isfinite(now_s) || now_s <= now_s_) {
    now_s = now_s_;
  }
  now_s = std::min(now_s, kLastTime_s);
  const bool command_pending = !rx_.empty() || rx_overflow_;
  const double end_s = last_rx_s_ + options_.end_of_command_gap_s;
  if (command_pending && end_s <= now_s) {
    run_boards_to(end_s);
    end_command(end_s);
  }
  run_boards_to(now_s);
  now_s_ = now_s;
}

void MotionMindBus::run_boards_to(double t_s) {
  const double behind_s = t_s - static_cast<double>(periods_) * kPeriod_s;
  if (behind_s > kMaxRunGap_s) {
    const auto skipped = static_cast<std::uint64_t>((behind_s - kMaxRunGap_s) / kPeriod_s);
    for (auto& board : boards_) board->jump(skipped);
    periods_ += skipped;
  }
  // The epsilon keeps a period that ends exactly at t_s from being lost to rounding.
  while (static_cast<double>(periods_ + 1) * kPeriod_s <= t_s + 1e-9) {
    ++periods_;
    for (auto& board : boards_) board->step(rng_);
  }
}

void MotionMindBus::end_command(double t_s) {
  const std::optional<mm::ParsedCommand> command =
      rx_overflow_ ? std::nullopt : mm::parse_command(rx_);
  rx_.clear();
  rx_overflow_ = false;
  if (!command) {
    ++rejected_commands_;
    return;
  }
  ++commands_;
  const bool broadcast = command->address == mm::kBroadcastAddress;
  for (auto& board : boards_) {
    if (!broadcast && board->address() != command->address) continue;
    Board::Answer answer = board->apply(*command);
    if (broadcast || !answer.reply) continue;
    send(std::move(*answer.reply),
         t_s + (answer.slow ? options_.write_store_delay_s : options_.response_delay_s));
  }
}

void MotionMindBus::send(mm::Packet reply, double start_s) {
  // Only a data reply carries a checksum; ACK is a bare byte.
  if (bad_checksums_ && reply.size() > 1) reply.back() ^= 0xFFu;
  const double byte_s = mm::wire_time_s(1, options_.baud);
  double t_s = std::max(start_s, tx_busy_until_s_);
  for (std::uint8_t byte : reply) {
    t_s += byte_s;
    tx_.push_back({t_s, byte});
  }
  tx_busy_until_s_ = t_s;
}

const MotionMindBus::Board* MotionMindBus::find(std::uint8_t address) const {
  for (const auto& board : boards_) {
    if (board->options().address == address) return board.get();
  }
  return nullptr;
}

MotionMindBaseCoupling::MotionMindBaseCoupling(const MotionMindBus& bus, std::uint8_t left_address,
                                               std::uint8_t right_address, EmulatedWorld& world,
                                               MotionMindBaseGeometry geometry)
    : bus_(bus),
      left_address_(left_address),
      right_address_(right_address),
      world_(world),
      geometry_(geometry) {
  const std::optional<double> left = bus.shaft_angle_rad(left_address);
  const std::optional<double> right = bus.shaft_angle_rad(right_address);
  if (!left || !right) throw std::invalid_argument("MotionMindBaseCoupling: unknown board");
  if (!finite_positive(geometry.track_m) || !finite_positive(geometry.wheel_radius_m)) {
    throw std::invalid_argument("MotionMindBaseCoupling: bad track or wheel radius");
  }
  last_left_rad_ = *left;
  last_right_rad_ = *right;
}

void MotionMindBaseCoupling::update() {
  const double left_rad = bus_.shaft_angle_rad(left_address_).value_or(last_left_rad_);
  const double right_rad = bus_.shaft_angle_rad(right_address_).value_or(last_right_rad_);
  const double left_m =
      (left_rad - last_left_rad_) * geometry_.wheel_radius_m * geometry_.left_sign;
  const double right_m =
      (right_rad - last_right_rad_) * geometry_.wheel_radius_m * geometry_.right_sign;
  last_left_rad_ = left_rad;
  last_right_rad_ = right_rad;
  if (left_m == 0.0 && right_m == 0.0) return;

  const double distance_m = 0.5 * (left_m + right_m);
  const double turn_rad = (right_m - left_m) / geometry_.track_m;
  geometry::Pose2D pose = world_.base_pose();
  if (std::abs(turn_rad) < 1e-9) {
    pose.x += distance_m * std::cos(pose.theta);
    pose.y += distance_m * std::sin(pose.theta);
  } else {
    const double radius_m = distance_m / turn_rad;
    pose.x += radius_m * (std::sin(pose.theta + turn_rad) - std::sin(pose.theta));
    pose.y -= radius_m * (std::cos(pose.theta + turn_rad) - std::cos(pose.theta));
  }
  pose.theta = geometry::wrap_angle(pose.theta + turn_rad);
  world_.set_base_pose(pose);
}

}  // namespace mobot::emulate
