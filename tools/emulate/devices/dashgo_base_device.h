#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "core/geometry/pose2d.h"
#include "drivers/protocol/line_framer.h"
#include "tools/emulate/devices/timed_replies.h"
#include "tools/emulate/emulated_device.h"
#include "tools/emulate/emulated_world.h"

namespace mobot::emulate {

struct DashgoBaseDeviceOptions {
  double wheel_radius_m = 0.064;
  double track_m = 0.3559;
  int ticks_per_wheel_rev = 1200;
  unsigned baud = 115200;
  // The wheel PID reaches its set-point with this time constant, and holds it within a few
  // percent (noise as a fraction of the speed).
  double wheel_time_constant_s = 0.1;
  double wheel_speed_noise_fraction = 0.02;
  // The sketch's own safety: no speed command for this long stops the motors.
  double auto_stop_s = 2.0;
  // How long the sketch takes to answer a command (parsing, the encoder read).
  double reply_delay_s = 0.001;
  // The body's radius: the emulated base stops at a wall instead of passing through it.
  double body_radius_m = 0.2;
  std::vector<geometry::Pose2D> sonars_in_base;  // empty: 'p' answers nothing
  double sonar_height_m = 0.1;
  double sonar_range_max_m = 0.8;
  double battery_v = 12.4;
  std::uint64_t seed = 1;
};

// The Dashgo D1's Arduino running the ROSArduinoBridge sketch, from the line's side: it answers
// b, e, r, m, u, p, v, j as the firmware does (replies end in CR LF, 16-bit encoder counts that
// wrap), drives its wheels toward the commanded ticks per 1/30 s, and moves the world's base by
// what the wheels turned: the closed loop the emulated lidar sees.
class DashgoBaseDevice final : public EmulatedDevice {
 public:
  DashgoBaseDevice(DashgoBaseDeviceOptions options, EmulatedWorld& world);

  std::string_view name() const override { return "base"; }
  void receive(std::span<const std::uint8_t> bytes, double now_s) override;
  std::vector<std::uint8_t> transmit(double now_s) override;
  void set_bad_checksums(bool on) override { garble_replies_ = on; }

  void set_estop_button(bool pressed) { estop_button_ = pressed; }
  // The set-points of the last speed command (ticks per 1/30 s), 0 once the sketch stopped.
  double target_left_tpf() const { return target_left_tpf_; }
  double target_right_tpf() const { return target_right_tpf_; }
  // The wheels' turned angle in ticks (not wrapped), for tests.
  double left_ticks() const { return left_ticks_; }
  double right_ticks() const { return right_ticks_; }

 private:
  void advance(double now_s);
  std::string answer(const std::string& command);
  std::string sonar_ranges() const;

  DashgoBaseDeviceOptions options_;
  EmulatedWorld& world_;
  protocol::LineFramer framer_;
  std::mt19937_64 rng_;
  double now_s_ = 0.0;
  double last_motor_command_s_ = 0.0;
  double target_left_tpf_ = 0.0;  // ticks per PID frame
  double target_right_tpf_ = 0.0;
  double left_tpf_ = 0.0;
  double right_tpf_ = 0.0;
  double left_ticks_ = 0.0;
  double right_ticks_ = 0.0;
  double left_ticks_zero_ = 0.0;
  double right_ticks_zero_ = 0.0;
  bool estop_button_ = false;
  bool garble_replies_ = false;
  TimedReplies replies_;
};

}  // namespace mobot::emulate
