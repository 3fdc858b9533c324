// libFuzzer target: the Dashgo Arduino's reply lines as the driver reads them (line framer, then
// the integer and OK parsers, then the 16-bit encoder unwrap), and the sketch's side of the line
// (the emulated base answering whatever arrives).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "drivers/protocol/line_framer.h"
#include "drivers/protocol/ros_arduino_bridge.h"

namespace bridge = mobot::protocol::arduino_bridge;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  // The first byte picks the read size, as a serial read returns whatever has arrived.
  const std::size_t chunk = 1 + data[0] % 64;
  const std::span<const std::uint8_t> bytes(data + 1, size - 1);
  for (const bool cr_ends_line : {false, true}) {
    mobot::protocol::LineFramer framer({.max_line_bytes = 64, .cr_ends_line = cr_ends_line});
    std::vector<std::string> lines;
    for (std::size_t at = 0; at < bytes.size(); at += chunk) {
      framer.feed(bytes.subspan(at, std::min(chunk, bytes.size() - at)), lines);
    }
    bridge::EncoderUnwrap unwrap;
    for (const std::string& line : lines) {
      if (line.size() > 64) __builtin_trap();
      bridge::is_ok(line);
      for (std::size_t count = 1; count <= 4; ++count) {
        if (const auto values = bridge::parse_integers(line, count)) {
          if (values->size() != count) __builtin_trap();
          unwrap.update((*values)[0]);
        }
      }
    }
  }
  return 0;
}
