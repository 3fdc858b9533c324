#pragma once

#include <chrono>
#include <memory>
#include <mutex>
#include <optional>

#include "core/msgs/laser_scan.h"
#include "drivers/hardware/laser_scan_source.h"
#include "drivers/protocol/ydlidar_scan.h"
#include "drivers/protocol/ydlidar_stream_parser.h"
#include "drivers/serial/device_thread.h"

namespace mobot::drivers::hardware {

struct YdlidarG4LaserOptions {
  serial::SerialOptions serial;  // 230400 baud
  protocol::ydlidar::SampleFormat format = protocol::ydlidar::SampleFormat::kDistance;
  protocol::ydlidar::LaserScanOptions scan;  // bins, range window, mount on the base
  // The head's turn rate the robot expects: a turn is overdue after three of its periods.
  double scan_rate_hz = 7.0;
  // The answers to device info and health come within this; the head spins up within
  // spin_up_s of the start command (the SDK waits about a second).
  std::chrono::milliseconds reply_timeout{500};
  double spin_up_s = 2.0;
  // Consecutive packets failing their checksum, with no good one between: the line is bad.
  int bad_packets_before_fault = 3;
};

// The YDLIDAR G4 on its USB serial adapter: device info and health at start (a head that reports
// an error is refused), the motor on (DTR) and scanning; packets are assembled into turns at
// the start-of-scan flag and each turn becomes a msgs::LaserScan. A turn that does not come
// within three periods makes the laser "silent"; packets that keep failing their checksum make
// it "checksum"; the device thread reopens it either way.
class YdlidarG4Laser final : public LaserScanSource {
 public:
  explicit YdlidarG4Laser(YdlidarG4LaserOptions options);
  ~YdlidarG4Laser() override;

  void start();
  void stop();
  // The newest scan since the last call, or nothing.
  std::optional<msgs::LaserScan> take_scan();

  void add_listener(Listener listener) override { listeners_.push_back(std::move(listener)); }
  DeviceStatus status() const override { return health_.status(); }
  const serial::DeviceHealth& health() const { return health_; }
  const YdlidarG4LaserOptions& options() const { return options_; }

 private:
  class Session;
  void session(serial::SerialPort& port, const std::stop_token& stop);

  YdlidarG4LaserOptions options_;
  serial::DeviceHealth health_{"laser"};
  std::vector<Listener> listeners_;
  mutable std::mutex mutex_;
  std::optional<msgs::LaserScan> scan_;
  std::unique_ptr<serial::DeviceThread> thread_;
};

}  // namespace mobot::drivers::hardware
