#pragma once

#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/msgs/ir_ring.h"
#include "core/safety/sharp_ir_curve.h"
#include "drivers/hardware/arduino_link.h"
#include "drivers/serial/device_thread.h"

namespace mobot::drivers::hardware {

struct SharpIrBoardOptions {
  serial::SerialOptions serial;  // the Mega's USB serial, 115200 baud
  // The analog pin of each sensor, in the order of sensors_in_base.
  std::vector<int> pins;
  std::vector<geometry::Pose2D> sensors_in_base;
  double cone_rad = 0.1;
  double rate_hz = 20.0;  // the ring is read whole this often
  safety::SharpIrCurveOptions curve;
  ArduinoLinkOptions link;
  double boot_timeout_s = 3.0;
};

// The Dashgo's ring of Sharp GP2Y0A21 rangers behind an Arduino Mega running the ROSArduinoBridge
// sketch: each cycle asks the ADC count of every sensor's pin (`a PIN`) and turns the counts into
// ranges through the robot's calibration curve (docs/algorithms.md R2).
class SharpIrBoard {
 public:
  explicit SharpIrBoard(SharpIrBoardOptions options);
  ~SharpIrBoard();

  void start();
  void stop();
  std::optional<msgs::IrRing> take_ring();
  const serial::DeviceHealth& health() const { return health_; }
  DeviceCounters counters() const { return health_.counters(); }
  const SharpIrBoardOptions& options() const { return options_; }

 private:
  void session(serial::SerialPort& port, const std::stop_token& stop);
  std::optional<msgs::IrRing> read_ring(ArduinoLink& link) const;

  SharpIrBoardOptions options_;
  safety::SharpIrCurve curve_;
  serial::DeviceHealth health_{"ir"};
  mutable std::mutex mutex_;
  std::optional<msgs::IrRing> ring_;
  std::unique_ptr<serial::DeviceThread> thread_;
};

}  // namespace mobot::drivers::hardware
