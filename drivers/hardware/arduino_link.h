#pragma once

#include <chrono>
#include <optional>
#include <stop_token>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/protocol/line_framer.h"
#include "drivers/serial/device_health.h"
#include "drivers/serial/serial_port.h"

namespace mobot::drivers::hardware {

struct ArduinoLinkOptions {
  // An Arduino answers within 2-3 ms at 115200 baud; a reply later than this is lost.
  std::chrono::milliseconds reply_timeout{25};
  // Consecutive unanswered commands that make the board "silent", and consecutive replies that
  // are not what the command asks for that make it "garbage" (one is noise on the line).
  int misses_before_silent = 2;
  int bad_replies_before_garbage = 3;
};

// Command and reply over one ROSArduinoBridge line, for a device thread: one command at a time,
// its reply line or nothing. Judges the board as it goes: throws serial::DeviceFault("silent")
// or ("garbage") when the board stops making sense; SerialError when the line fails.
class ArduinoLink {
 public:
  ArduinoLink(serial::SerialPort& port, serial::DeviceHealth& health, ArduinoLinkOptions options);

  // Sends `command` (with its CR) and returns the reply line, or nothing within the time-out.
  std::optional<std::string> ask(std::string_view command);
  // The reply as `count` integers; a missing or malformed reply counts against the board.
  std::optional<std::vector<long>> ask_integers(std::string_view command, std::size_t count);
  // The reply must be "OK".
  bool ask_ok(std::string_view command);
  // The sketch restarts when the port opens (DTR) and its boot loader eats what comes for about a
  // second: asks its baud rate until it answers (returns), `stop` is requested, or `timeout_s`
  // passes (DeviceFault "silent").
  void await_boot(const std::stop_token& stop, double timeout_s);

 private:
  void judge(bool answered, bool well_formed);

  serial::SerialPort& port_;
  serial::DeviceHealth& health_;
  ArduinoLinkOptions options_;
  protocol::LineFramer framer_;
  std::vector<std::string> lines_;
  int misses_ = 0;
  int bad_replies_ = 0;
};

}  // namespace mobot::drivers::hardware
