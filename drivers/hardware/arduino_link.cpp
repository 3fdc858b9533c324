#include "drivers/hardware/arduino_link.h"

#include <array>

#include "drivers/protocol/ros_arduino_bridge.h"
#include "drivers/serial/device_thread.h"

namespace mobot::drivers::hardware {

namespace bridge = protocol::arduino_bridge;

ArduinoLink::ArduinoLink(serial::SerialPort& port, serial::DeviceHealth& health,
                         ArduinoLinkOptions options)
    : port_(port), health_(health), options_(options) {}

std::optional<std::string> ArduinoLink::ask(std::string_view command) {
  // A reply that came after its time-out must not be taken for the answer to this command.
  port_.discard_input();
  framer_.reset();
  lines_.clear();
  port_.write_all(command, options_.reply_timeout);
  const auto deadline = std::chrono::steady_clock::now() + options_.reply_timeout;
  std::array<std::uint8_t, 256> buffer{};
  while (lines_.empty()) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return std::nullopt;
    const std::size_t count = port_.read_some(buffer, left);
    health_.add_bytes(count);
    framer_.feed(std::span(buffer.data(), count), lines_);
  }
  return lines_.front();
}

std::optional<std::vector<long>> ArduinoLink::ask_integers(std::string_view command,
                                                           std::size_t count) {
  const std::optional<std::string> reply = ask(command);
  std::optional<std::vector<long>> values;
  if (reply) values = bridge::parse_integers(*reply, count);
  judge(reply.has_value(), values.has_value());
  return values;
}

bool ArduinoLink::ask_ok(std::string_view command) {
  const std::optional<std::string> reply = ask(command);
  const bool ok = reply && bridge::is_ok(*reply);
  judge(reply.has_value(), ok);
  return ok;
}

void ArduinoLink::await_boot(const std::stop_token& stop, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!stop.stop_requested() && !ask(bridge::command(bridge::kGetBaud))) {
    if (std::chrono::steady_clock::now() > deadline) throw serial::DeviceFault("silent");
  }
}

void ArduinoLink::judge(bool answered, bool well_formed) {
  misses_ = answered ? 0 : misses_ + 1;
  bad_replies_ = !answered || well_formed ? 0 : bad_replies_ + 1;
  if (answered && !well_formed) health_.add_checksum_error();
  if (misses_ >= options_.misses_before_silent) throw serial::DeviceFault("silent");
  if (bad_replies_ >= options_.bad_replies_before_garbage) throw serial::DeviceFault("garbage");
}

}  // namespace mobot::drivers::hardware
