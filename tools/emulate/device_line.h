#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <string>

#include "tools/emulate/emulated_device.h"
#include "tools/emulate/pty_port.h"

namespace mobot::emulate {

// The faults a line can be given, whatever the protocol.
enum class LineFault {
  kNone,
  kDrop,      // the device hears the host but what it sends is lost: a silent device
  kStall,     // the device neither reads nor sends (a hung firmware); it resumes afterwards
  kGarbage,   // what arrives is noise (a wrong baud rate, a bad ground)
  kChecksum,  // frames arrive with wrong checksums (the model spoils them)
  kUnplug,    // the cable is out: the pty is gone, and reappears when the fault ends
};

// "drop", "stall", ... -> the fault; nothing for a word that is not one.
std::optional<LineFault> line_fault_named(const std::string& name);

// One emulated device on its pty: shuttles bytes between the line and the model and applies
// the fault it was given, for a while or until cleared.
class DeviceLine {
 public:
  DeviceLine(std::unique_ptr<EmulatedDevice> device, std::filesystem::path link_path,
             std::uint64_t seed);

  EmulatedDevice& device() { return *device_; }
  const PtyPort& port() const { return port_; }

  // One pass: what the host wrote goes to the model, what the model sends goes out.
  void step(double now_s);
  // `duration_s` <= 0: until cleared.
  void set_fault(LineFault fault, double now_s, double duration_s);
  void clear_fault();
  LineFault fault() const { return fault_; }

  // Latency tracing. A mark is an output offset of the model (bytes its transmit() has returned,
  // counted from the start, the marked byte included); once the pty has taken that byte,
  // `written` gets the CLOCK_REALTIME time in microseconds, read as the write returns. A marked
  // byte that never reaches the pty (a fault, a full pty buffer) drops its mark.
  void set_mark_listener(std::function<void(std::int64_t realtime_us)> written);
  void add_output_mark(std::uint64_t end_offset);

 private:
  // Settles the marks within the model's output [begin, begin + size) of which `written` bytes
  // reached the pty.
  void settle_marks(std::uint64_t begin, std::size_t size, std::size_t written);

  std::unique_ptr<EmulatedDevice> device_;
  PtyPort port_;
  std::mt19937_64 rng_;
  LineFault fault_ = LineFault::kNone;
  double fault_until_s_ = 0.0;
  double last_step_s_ = 0.0;
  std::uint64_t model_offset_ = 0;  // bytes the model has sent, written or not
  std::deque<std::uint64_t> marks_;
  std::function<void(std::int64_t)> mark_written_;
};

}  // namespace mobot::emulate
