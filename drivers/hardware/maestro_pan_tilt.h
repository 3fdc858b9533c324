#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <stop_token>
#include <string>
#include <vector>

#include "core/msgs/head_range.h"
#include "core/vision/pan_tilt_head.h"
#include "drivers/device_status.h"
#include "drivers/pan_tilt_driver.h"
#include "drivers/protocol/pololu_maestro.h"
#include "drivers/serial/device_health.h"
#include "drivers/serial/device_thread.h"
#include "drivers/serial/serial_port.h"

namespace mobot::drivers::hardware {

// One of the head's hobby servos on a Maestro channel.
struct MaestroServoOptions {
  int channel = 0;
  protocol::maestro::ServoCalibration calibration;
  // The Maestro's acceleration limit for the servo; 0: none (the speed limit is the head's rate).
  double max_accel_rad_s2 = 0.0;
};

// R4's head as far as a standard hobby servo turns it: +/-90 deg of pan (R4's +/-170 deg needs
// more than a hobby servo's travel).
inline vision::PanTiltHeadOptions hobby_servo_head() {
  vision::PanTiltHeadOptions head;
  head.min_pan_rad = -1.5707963267948966;
  head.max_pan_rad = 1.5707963267948966;
  return head;
}

struct MaestroPanTiltOptions {
  // The Maestro's command port (USB: /dev/ttyACM0, whose baud rate does not matter) or its TTL
  // serial line at the rate set in its Serial Settings.
  serial::SerialOptions serial{.device = {}, .baud = 115200, .dtr = {}, .rts = {}};
  // The health's name on /metrics.
  std::string name = "pan_tilt";
  // Geometry, joint limits and slew rates; the rates become the servos' speed limits, which the
  // Maestro enforces.
  vision::PanTiltHeadOptions head = hobby_servo_head();
  MaestroServoOptions pan{0, {}, 0.0};
  MaestroServoOptions tilt{1, {}, 0.0};
  // The ultrasonic ranger's analog input (0-11); nothing: a head without one.
  std::optional<int> range_channel = 2;
  protocol::maestro::RangerScale ranger;
  // The poll cycle: targets out, positions, range and errors in.
  double rate_hz = 50.0;
  // The Maestro's "Enable CRC" (Serial Settings): every command then carries its CRC-7.
  bool crc = false;
  // Over USB the Maestro answers within a few milliseconds; the line time of the bytes is added.
  std::chrono::milliseconds reply_timeout{25};
  // Consecutive unanswered polls that make the device "silent", consecutive answers that cannot be
  // the Maestro's (too few or too many bytes, impossible values) that make it "garbage" (one is
  // noise), and consecutive polls whose error register is not clear that make it "refused".
  int misses_before_silent = 2;
  int bad_replies_before_garbage = 3;
  int error_polls_before_refused = 3;
};

// R4's pan/tilt head on a Pololu Maestro (Micro Maestro 6 or a Mini Maestro): two hobby servos
// and the MaxBotix LV-EZ ranger that looks along the camera's axis on an analog input, on the
// driver's own device thread (docs/api.md, "Hardware").
//
// Each session asks for the error register (which also clears it) until the Maestro answers, sets
// each servo's speed (from the head's rates) and acceleration limits, then cycles at rate_hz:
// one write with both servos' targets and the queries (the positions of both servos and the
// ranger's input, and the error register), then the eight bytes of their answers. Targets go out
// every cycle: an error sends the Maestro's servos to their "on startup or error" setting (off by
// default), and the next cycle puts them back. current() is the pulses the Maestro reports,
// converted through each servo's calibration (before the first report, the target: the first
// pulse after power-up jumps there, the Maestro not knowing where an unpowered servo stands).
// The answers have no framing or checksum: a poll whose bytes are too few or too many, or whose
// values the Maestro cannot send, counts as garbage. set_target clamps and never blocks.
class MaestroPanTilt final : public PanTiltDriver {
 public:
  // Throws std::invalid_argument, the message starting with the config key at fault: a channel
  // outside 0-23 (the ranger's outside the analog 0-11) or used twice, a calibration or limit
  // whose pulse the Maestro cannot make, a rate or time-out that is not positive, head options
  // vision::PanTiltHead refuses.
  explicit MaestroPanTilt(MaestroPanTiltOptions options);
  ~MaestroPanTilt() override;
  MaestroPanTilt(const MaestroPanTilt&) = delete;
  MaestroPanTilt& operator=(const MaestroPanTilt&) = delete;

  void start();
  void stop();

  const vision::PanTiltHeadOptions& head() const override { return head_.options(); }
  void set_target(const vision::PanTilt& joints) override;
  vision::PanTilt target() const override;
  vision::PanTilt current() const override;
  DeviceStatus status() const override { return health_.status(); }

  // The ranger's newest reading since the last call (unstamped), or nothing.
  std::optional<msgs::HeadRange> take_range();
  const MaestroPanTiltOptions& options() const { return options_; }
  const serial::DeviceHealth& health() const { return health_; }
  DeviceCounters counters() const { return health_.counters(); }
  // Polls answered since start, and the last error register that was not clear.
  std::uint64_t polls() const { return polls_.load(std::memory_order_relaxed); }
  std::uint16_t last_errors() const { return last_errors_.load(std::memory_order_relaxed); }

 private:
  void session(serial::SerialPort& port, const std::stop_token& stop);
  void configure_servos(serial::SerialPort& port);
  protocol::maestro::Packet command(protocol::maestro::Packet packet) const;
  protocol::maestro::Packet cycle_commands() const;
  // One write and its answers; judged, so it may throw serial::DeviceFault.
  std::optional<std::vector<std::uint16_t>> exchange(
      serial::SerialPort& port, const protocol::maestro::Packet& commands,
      const std::vector<protocol::maestro::Query>& queries);
  bool plausible(const std::vector<std::uint16_t>& values) const;
  void judge(bool answered, bool well_formed);
  void note_errors(std::uint16_t errors);
  void record(const std::vector<std::uint16_t>& values);

  MaestroPanTiltOptions options_;
  vision::PanTiltHead head_;
  serial::DeviceHealth health_;
  std::vector<protocol::maestro::Query> poll_queries_;
  // The device thread's own.
  protocol::maestro::ReplyCollector collector_;
  int misses_ = 0;
  int bad_replies_ = 0;
  int error_polls_ = 0;
  // Shared with the control loop (mutex_).
  mutable std::mutex mutex_;
  vision::PanTilt target_;
  std::optional<double> current_pan_rad_;
  std::optional<double> current_tilt_rad_;
  std::optional<msgs::HeadRange> range_;
  std::atomic<std::uint64_t> polls_{0};
  std::atomic<std::uint16_t> last_errors_{0};
  std::unique_ptr<serial::DeviceThread> thread_;
};

}  // namespace mobot::drivers::hardware
