#include "drivers/modbus/modbus_rtu_bus.h"

#include <modbus/modbus.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "core/geometry/pose2d.h"
#include "core/numeric/finite.h"
#include "drivers/modbus/modbus_frame_bytes.h"

namespace mobot::drivers::modbus {
namespace {

// The rates libmodbus turns into termios speeds; it opens any other at 9600 without a word.
constexpr std::array kBauds = {110,     300,     600,     1200,    2400,    4800,    9600,   19200,
                               38400,   57600,   115200,  230400,  460800,  500000,  576000, 921600,
                               1000000, 1152000, 1500000, 2500000, 3000000, 3500000, 4000000};
constexpr int kCompassTenthsPerTurn = 3600;

int reply_bytes(NodeKind kind) {
  return kind == NodeKind::kLimitSwitch ? kBitsReplyBytes : kRegisterReplyBytes;
}

BusClock::duration duration(double seconds) {
  return std::chrono::duration_cast<BusClock::duration>(std::chrono::duration<double>(seconds));
}

void check(const ModbusRtuBusOptions& options) {
  if (options.device_path.empty()) throw std::invalid_argument("modbus bus: no device path");
  if (std::find(kBauds.begin(), kBauds.end(), options.baud) == kBauds.end()) {
    throw std::invalid_argument("modbus bus: a baud rate the serial port does not know: " +
                                std::to_string(options.baud));
  }
  if (!finite_positive(options.response_timeout_s) || options.response_timeout_s >= 60.0 ||
      !finite_positive(options.silent_timeout_s) || !finite_positive(options.reopen_period_s)) {
    throw std::invalid_argument(
        "modbus bus: the time-out is in (0, 60) s, the silence and reopen periods positive");
  }
}

PollScheduleOptions checked_schedule_options(const ModbusRtuBusOptions& options) {
  check(options);
  return {.compass_node = options.compass_node,
          .sonar_nodes = options.sonar_nodes,
          .limit_switch_node = options.limit_switch_node,
          .compass_rate_hz = options.compass_rate_hz,
          .sonar_rate_hz = options.sonar_rate_hz,
          .limit_switch_rate_hz = options.limit_switch_rate_hz,
          .baud = options.baud,
          .turnaround_s = options.turnaround_s,
          .max_bus_load = options.max_bus_load,
          .failures_before_not_ok = options.failures_before_not_ok,
          .retry_period_s = options.retry_period_s};
}

// What a failed read says; nothing when the device itself is gone (or in a state no read will
// leave), which the caller answers by reopening it.
std::optional<ReadFailure> classify(int error) {
  if (error == ETIMEDOUT) return ReadFailure{ReadError::kTimeout};
  if (error == EMBBADCRC) return ReadFailure{ReadError::kCrc};
  if (error > MODBUS_ENOBASE && error < MODBUS_ENOBASE + MODBUS_EXCEPTION_MAX) {
    return ReadFailure{ReadError::kException, error - MODBUS_ENOBASE};
  }
  if (error == EMBBADDATA || error == EMBBADEXC || error == EMBUNKEXC || error == EMBMDATA ||
      error == EMBBADSLAVE) {
    return ReadFailure{ReadError::kBadReply};
  }
  return std::nullopt;
}

}  // namespace

void ModbusRtuBus::ContextFree::operator()(modbus_t* context) const { modbus_free(context); }

ModbusRtuBus::ModbusRtuBus(const ModbusRtuBusOptions& options)
    : options_(options),
      epoch_(BusClock::now()),
      schedule_(checked_schedule_options(options)),
      sonars_(options.sonar_nodes.size()) {
  context_.reset(modbus_new_rtu(options_.device_path.c_str(), options_.baud, 'N', 8, 1));
  if (!context_) {
    throw std::invalid_argument(std::string("modbus bus: ") + modbus_strerror(errno));
  }
  const auto timeout_us =
      static_cast<std::uint32_t>(std::lround(options_.response_timeout_s * 1e6));
  const std::uint32_t whole_s = timeout_us / 1000000;
  const std::uint32_t rest_us = timeout_us % 1000000;
  // No byte time-out: the whole reply must come within the response time-out, so a reply cut
  // short costs that time-out and not libmodbus's default half second per missing byte.
  const bool timeouts_set = modbus_set_response_timeout(context_.get(), whole_s, rest_us) == 0 &&
                            modbus_set_byte_timeout(context_.get(), 0, 0) == 0;
  if (!timeouts_set) {
    throw std::invalid_argument(std::string("modbus bus: ") + modbus_strerror(errno));
  }
}

ModbusRtuBus::~ModbusRtuBus() { stop(); }

void ModbusRtuBus::start() {
  if (thread_.joinable()) return;
  {
    const std::lock_guard lock(mutex_);
    link_ = Link::kMissing;
  }
  thread_ = std::jthread([this](const std::stop_token& stop) { run(stop); });
}

void ModbusRtuBus::stop() {
  if (!thread_.joinable()) return;
  thread_.request_stop();
  thread_.join();
}

std::optional<CompassSample> ModbusRtuBus::compass() const {
  const std::lock_guard lock(mutex_);
  return compass_;
}

std::vector<std::optional<SonarSample>> ModbusRtuBus::sonars() const {
  const std::lock_guard lock(mutex_);
  return sonars_;
}

std::optional<LimitSwitchSample> ModbusRtuBus::limit_switch() const {
  const std::lock_guard lock(mutex_);
  return limit_switch_;
}

std::vector<NodeHealth> ModbusRtuBus::node_health() const {
  const std::lock_guard lock(mutex_);
  return schedule_.health();
}

ModbusBusCounters ModbusRtuBus::counters() const {
  const std::lock_guard lock(mutex_);
  return counters_;
}

DeviceCounters ModbusRtuBus::device_counters(std::string name) const {
  DeviceCounters out;
  out.name = std::move(name);
  out.status = status();
  const std::lock_guard lock(mutex_);
  out.bytes = counters_.reply_bytes;
  out.frames = counters_.replies;
  out.checksum_errors = counters_.crc_errors + counters_.bad_replies;
  out.reconnects = counters_.reconnects;
  return out;
}

double ModbusRtuBus::round_s() const {
  const std::lock_guard lock(mutex_);
  return schedule_.round_s();
}

double ModbusRtuBus::effective_rate_hz(NodeKind kind) const {
  const std::lock_guard lock(mutex_);
  return schedule_.effective_rate_hz(kind);
}

DeviceStatus ModbusRtuBus::status() const {
  const auto now = BusClock::now();
  const std::lock_guard lock(mutex_);
  switch (link_) {
    case Link::kStopped:
      return {false, "stopped"};
    case Link::kMissing:
      return {false, "missing"};
    case Link::kOpen:
      break;
  }
  const BusClock::duration silence = duration(options_.silent_timeout_s);
  const bool heard = last_reply_at_ && *last_reply_at_ >= opened_at_;
  const BusClock::time_point since = heard ? *last_reply_at_ : opened_at_;
  if (now - since < silence)
    return heard ? DeviceStatus{true, ""} : DeviceStatus{false, "starting"};
  if (last_crc_error_at_ && *last_crc_error_at_ >= since) return {false, "crc"};
  return {false, "silent"};
}

void ModbusRtuBus::run(const std::stop_token& stop) {
  while (!stop.stop_requested()) {
    // Nothing may leave the thread; whatever went wrong, the device is reopened after a pause.
    try {
      if (link_ != Link::kOpen && !open()) {
        wait_until(stop, BusClock::now() + duration(options_.reopen_period_s));
        continue;
      }
      std::optional<PollTarget> target;
      BusClock::time_point due;
      {
        const std::lock_guard lock(mutex_);
        target = schedule_.next(seconds(BusClock::now()));
        if (!target) {
          due = epoch_ + duration(schedule_.next_due_s());
        }
      }
      if (!target) {
        wait_until(stop, due);
      } else if (!read(*target)) {
        close(true);
      }
    } catch (...) {
      close(true);
      wait_until(stop, BusClock::now() + duration(options_.reopen_period_s));
    }
  }
  close(false);
}

bool ModbusRtuBus::open() {
  modbus_t* context = context_.get();
  bool opened = modbus_connect(context) == 0;
  if (opened && options_.rs485_mode &&
      modbus_rtu_set_serial_mode(context, MODBUS_RTU_RS485) == -1) {
    modbus_close(context);
    opened = false;
  }
  // Whatever the port buffered while nobody read it is stale.
  if (opened) modbus_flush(context);
  const auto now = BusClock::now();
  const std::lock_guard lock(mutex_);
  if (!opened) {
    ++counters_.open_failures;
    link_ = Link::kMissing;
    return false;
  }
  if (opened_before_) ++counters_.reconnects;
  opened_before_ = true;
  opened_at_ = now;
  link_ = Link::kOpen;
  schedule_.restart(seconds(now));
  return true;
}

void ModbusRtuBus::close(bool lost) {
  // Closing a context that is not open is harmless: libmodbus checks its descriptor.
  modbus_close(context_.get());
  const std::lock_guard lock(mutex_);
  if (lost) {
    if (link_ == Link::kOpen) schedule_.link_lost();
    link_ = Link::kMissing;
  } else {
    link_ = Link::kStopped;
  }
}

bool ModbusRtuBus::read(const PollTarget& target) {
  modbus_t* context = context_.get();
  modbus_set_slave(context, target.node);
  std::uint16_t word = 0;
  std::uint8_t bit = 0;
  const int values = target.kind == NodeKind::kLimitSwitch
                         ? modbus_read_input_bits(context, 0, 1, &bit)
                         : modbus_read_input_registers(context, 0, 1, &word);
  const int error = errno;
  const auto now = BusClock::now();
  if (values == 1) {
    take_reply(target, word, bit != 0, now);
    return true;
  }
  const std::optional<ReadFailure> failure = classify(error);
  if (!failure) {
    const std::lock_guard lock(mutex_);
    ++counters_.requests;
    ++counters_.link_errors;
    return false;
  }
  take_failure(target, *failure, now);
  // The rest of a cut reply, or a late one, would be taken for the next node's.
  if (failure->error != ReadError::kException) modbus_flush(context);
  return true;
}

void ModbusRtuBus::take_reply(const PollTarget& target, std::uint16_t word, bool bit,
                              BusClock::time_point now) {
  const std::lock_guard lock(mutex_);
  ++counters_.requests;
  ++counters_.replies;
  counters_.reply_bytes += reply_bytes(target.kind);
  last_reply_at_ = now;
  switch (target.kind) {
    case NodeKind::kCompass: {
      if (word >= kCompassTenthsPerTurn) {
        ++counters_.bad_replies;
        schedule_.record_failure(target.node, {ReadError::kBadReply}, seconds(now));
        return;
      }
      const double compass_rad = word * 2.0 * std::numbers::pi / kCompassTenthsPerTurn;
      compass_ = CompassSample{
          .heading_rad = geometry::wrap_angle(options_.heading_offset_rad - compass_rad),
          .received = now,
          .count = compass_ ? compass_->count + 1 : 1};
      break;
    }
    case NodeKind::kSonar: {
      std::optional<SonarSample>& sample = sonars_[target.sonar_index];
      const std::uint64_t count = sample ? sample->count + 1 : 1;
      sample =
          SonarSample{.range_m = word == 0 ? std::nullopt : std::optional<double>(word / 1000.0),
                      .received = now,
                      .count = count};
      break;
    }
    case NodeKind::kLimitSwitch:
      limit_switch_ = LimitSwitchSample{
          .pressed = bit, .received = now, .count = limit_switch_ ? limit_switch_->count + 1 : 1};
      break;
  }
  schedule_.record_success(target.node, seconds(now));
}

void ModbusRtuBus::take_failure(const PollTarget& target, const ReadFailure& failure,
                                BusClock::time_point now) {
  const std::lock_guard lock(mutex_);
  ++counters_.requests;
  switch (failure.error) {
    case ReadError::kTimeout:
      ++counters_.timeouts;
      break;
    case ReadError::kCrc:
      ++counters_.crc_errors;
      counters_.reply_bytes += reply_bytes(target.kind);
      last_crc_error_at_ = now;
      break;
    case ReadError::kException:
      // An exception is a reply: the node is there and said no.
      ++counters_.replies;
      ++counters_.exceptions;
      counters_.reply_bytes += kExceptionReplyBytes;
      last_reply_at_ = now;
      break;
    case ReadError::kBadReply:
      ++counters_.bad_replies;
      break;
  }
  schedule_.record_failure(target.node, failure, seconds(now));
}

void ModbusRtuBus::wait_until(const std::stop_token& stop, BusClock::time_point deadline) {
  std::unique_lock lock(mutex_);
  wake_.wait_until(lock, stop, deadline, [] { return false; });
}

double ModbusRtuBus::seconds(BusClock::time_point time) const {
  return std::chrono::duration<double>(time - epoch_).count();
}

}  // namespace mobot::drivers::modbus
