#include "drivers/protocol/ros_arduino_bridge.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>

namespace mobot::protocol::arduino_bridge {

std::string command(char letter) { return std::string(1, letter) + '\r'; }

std::string motor_speeds_command(int left_ticks_per_frame, int right_ticks_per_frame) {
  return std::string(1, kMotorSpeeds) + ' ' + std::to_string(left_ticks_per_frame) + ' ' +
         std::to_string(right_ticks_per_frame) + '\r';
}

std::string update_pid_command(const PidGains& gains) {
  return std::string(1, kUpdatePid) + ' ' + std::to_string(gains.kp) + ':' +
         std::to_string(gains.kd) + ':' + std::to_string(gains.ki) + ':' +
         std::to_string(gains.ko) + '\r';
}

std::string analog_read_command(int pin) {
  return std::string(1, kAnalogRead) + ' ' + std::to_string(pin) + '\r';
}

std::optional<std::vector<long>> parse_integers(std::string_view line, std::size_t count) {
  std::vector<long> values;
  std::size_t at = 0;
  while (at < line.size()) {
    if (line[at] == ' ') {
      ++at;
      continue;
    }
    long value = 0;
    const char* begin = line.data() + at;
    const char* end = line.data() + line.size();
    const auto [next, error] = std::from_chars(begin, end, value);
    // A 32-bit long on the AVR: anything wider is noise, not a count.
    if (error != std::errc() || next == begin || value > 2147483647L || value < -2147483648L) {
      return std::nullopt;
    }
    if (next != end && *next != ' ') return std::nullopt;
    values.push_back(value);
    if (values.size() > count) return std::nullopt;
    at = static_cast<std::size_t>(next - line.data());
  }
  if (values.size() != count) return std::nullopt;
  return values;
}

bool is_ok(std::string_view line) { return line == kOk; }

int ticks_per_frame(double wheel_radps, int ticks_per_wheel_rev) {
  const double ticks = wheel_radps / (2.0 * std::numbers::pi) * ticks_per_wheel_rev / kPidRateHz;
  // The firmware's set-point is an int; a NaN from upstream must not become one.
  if (!std::isfinite(ticks)) return 0;
  return static_cast<int>(std::lround(std::clamp(ticks, -30000.0, 30000.0)));
}

double wheel_radps(double ticks_per_frame, int ticks_per_wheel_rev) {
  return ticks_per_frame * kPidRateHz * 2.0 * std::numbers::pi / ticks_per_wheel_rev;
}

std::int64_t EncoderUnwrap::update(long raw_count) {
  const auto raw = static_cast<std::uint16_t>(static_cast<std::uint32_t>(raw_count) & 0xFFFFU);
  if (!started_) {
    started_ = true;
    last_raw_ = raw;
    total_ = static_cast<std::int16_t>(raw);
    return total_;
  }
  total_ += static_cast<std::int16_t>(static_cast<std::uint16_t>(raw - last_raw_));
  last_raw_ = raw;
  return total_;
}

}  // namespace mobot::protocol::arduino_bridge
