#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/msgs/sonar_ring.h"
#include "core/msgs/wheel_command.h"
#include "drivers/hardware/arduino_link.h"
#include "drivers/protocol/ros_arduino_bridge.h"
#include "drivers/serial/device_thread.h"

namespace mobot::drivers::hardware {

struct DashgoBoardOptions {
  serial::SerialOptions serial;  // 115200 baud
  int ticks_per_wheel_rev = 1200;
  protocol::arduino_bridge::PidGains pid;  // the Dashgo's own defaults
  // One set-point and one encoder read per cycle: the rate the odometry sees the wheels at.
  double poll_rate_hz = 50.0;
  // The slower reads take turns after the encoders: the sonars and the button every this many
  // cycles (10 Hz at 50 Hz), the battery every battery_every cycles.
  int sonar_every = 5;
  int battery_every = 50;
  ArduinoLinkOptions link;
  // The firmware resets when the port opens (DTR) and boots for about a second; it is asked for
  // its baud rate until it answers or this passes.
  double boot_timeout_s = 3.0;
  // The sonars' mounts and beams, for the ring mobot reads (docs/algorithms.md R2).
  std::vector<geometry::Pose2D> sonars_in_base;
  double sonar_cone_rad = 0.3;
  double sonar_range_min_m = 0.03;
  double sonar_range_max_m = 0.8;
};

// The Dashgo D1's Arduino base controller (ROSArduinoBridge firmware) on its own thread: each
// cycle it sends the wheel set-points and reads the encoders; every few cycles the sonars and the
// emergency button, now and then the battery. The control loop reads the newest values without
// waiting. The firmware stops the motors by itself when no set-point came for 2 s.
class DashgoBoard {
 public:
  explicit DashgoBoard(DashgoBoardOptions options);
  ~DashgoBoard();

  void start();
  void stop();

  void set_wheel_command(const msgs::WheelCommand& command);
  // The cumulative counts read since the last call, or nothing.
  struct Counts {
    std::int64_t left_ticks = 0;
    std::int64_t right_ticks = 0;
  };
  std::optional<Counts> take_counts();
  // The newest sonar ring since the last call (ranges in metres), or nothing.
  std::optional<msgs::SonarRing> take_sonar();
  bool estop_button_pressed() const;
  double battery_v() const;

  const serial::DeviceHealth& health() const { return health_; }
  // The health's counters and the battery, once read.
  DeviceCounters counters() const;
  const DashgoBoardOptions& options() const { return options_; }

 private:
  void session(serial::SerialPort& port, const std::stop_token& stop);
  void boot(ArduinoLink& link, const std::stop_token& stop);
  void cycle(ArduinoLink& link, int cycle_index);
  msgs::SonarRing sonar_ring(const std::vector<long>& ranges_cm) const;

  DashgoBoardOptions options_;
  serial::DeviceHealth health_{"base"};
  mutable std::mutex mutex_;
  msgs::WheelCommand command_;
  std::optional<Counts> counts_;
  std::optional<msgs::SonarRing> sonar_;
  bool estop_button_ = false;
  double battery_v_ = 0.0;
  protocol::arduino_bridge::EncoderUnwrap left_unwrap_;
  protocol::arduino_bridge::EncoderUnwrap right_unwrap_;
  std::unique_ptr<serial::DeviceThread> thread_;
};

}  // namespace mobot::drivers::hardware
