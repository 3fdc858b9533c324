#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace mobot::emulate {

// One device as the host sees it through its serial line: it reads what the host wrote and sends
// bytes back as time passes. A model is pure: time comes in as an argument (seconds since the
// emulator started), so a test drives it without a pty and the same inputs give the same bytes.
// Faults that do not depend on the protocol (drop, stall, garbage, unplug) are the pty wrapper's;
// a model only knows how to spoil its own checksums (set_bad_checksums).
class EmulatedDevice {
 public:
  virtual ~EmulatedDevice() = default;

  virtual std::string_view name() const = 0;
  // Bytes the host wrote, in order, as they arrived by `now_s`.
  virtual void receive(std::span<const std::uint8_t> bytes, double now_s) = 0;
  // Lets time run to `now_s` (never backwards) and returns what the device sent meanwhile.
  virtual std::vector<std::uint8_t> transmit(double now_s) = 0;
  // While on, every frame that carries a checksum or CRC goes out with a wrong one.
  virtual void set_bad_checksums(bool on) = 0;
};

}  // namespace mobot::emulate
