#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <stop_token>
#include <string>

#include "core/geometry/pose2d.h"
#include "core/msgs/laser_scan.h"
#include "drivers/hardware/laser_scan_source.h"
#include "drivers/protocol/sick_lms2xx_commands.h"
#include "drivers/protocol/sick_lms2xx_telegram.h"
#include "drivers/serial/device_thread.h"

namespace mobot::drivers::hardware {

struct SickLms2xxLaserOptions {
  // The device, and the rate the scans stream at: 38400 (any RS-232 port) or 500000 (an RS-422
  // card or adapter). The line always opens at 9600, the rate an LMS talks after power-on.
  serial::SerialOptions serial{.device = {}, .baud = 38400, .dtr = {}, .rts = {}};
  // 1 or 0.5 deg as complete scans; 0.25 deg as interlaced parts, which only 500000 baud carries.
  protocol::sick::AngularResolution resolution = protocol::sick::AngularResolution::kHalfDeg;
  geometry::Pose2D sensor_in_base{0.2, 0.0, 0.0};
  double range_min_m = 0.4;
  double range_max_m = 80.0;
  // Quiet after a request (or after the last byte that came) that counts as no answer: the LMS
  // acknowledges within 60 ms, once the telegram it is sending is out.
  double ack_timeout_s = 0.1;
  // From the acknowledgement to the reply: a variant switch takes the LMS a few hundred ms.
  double reply_timeout_s = 1.0;
  // Sends of one request before the LMS counts as silent (or refusing, when it said NAK).
  int request_tries = 3;
  // Telegrams in a row that fail their CRC, none good between them: the line is bad.
  int bad_crc_limit = 3;
  // No complete scan for 3 scan periods, or at least this long: the laser is silent.
  double min_silence_s = 0.3;
};

// Complete scans per second the LMS sends at `baud_bps` and `resolution` over 180 deg. The mirror
// turns at 75 Hz and a scan goes out only when the line is idle the moment it is ready: at 38400
// baud 9.4 Hz at 1 deg and 4.7 Hz at 0.5 deg; at 500000 baud 75, 37.5 and (four interlaced parts
// a scan) 18.75 Hz.
double sick_lms2xx_scan_rate_hz(unsigned baud_bps, protocol::sick::AngularResolution resolution);

// A SICK LMS 200/211/291 on its serial line, on its own device thread. Each session finds the
// rate the LMS talks (9600 after power-on, else 19200, 38400 or 500000), switches it to the
// configured rate, sets the 180 deg variant at the configured resolution, reads the range bits
// from its status and starts continuous output; then every scan is decoded, handed to the
// listener and kept for take_scan(). A silent laser, telegrams that keep failing their CRC, or a
// refused request end the session ("silent", "checksum", "refused"); the thread reopens the line.
// Stopping asks the LMS to stop streaming.
class SickLms2xxLaser final : public LaserScanSource {
 public:
  // Throws std::invalid_argument for a baud rate the LMS does not stream at or 0.25 deg at 38400.
  explicit SickLms2xxLaser(SickLms2xxLaserOptions options);
  ~SickLms2xxLaser() override;
  SickLms2xxLaser(const SickLms2xxLaser&) = delete;
  SickLms2xxLaser& operator=(const SickLms2xxLaser&) = delete;

  void start();
  void stop();

  // The newest scan since the last call (sensor frame, stamp 0: the poller stamps it), or nothing.
  std::optional<msgs::LaserScan> take_scan();
  void add_listener(Listener listener) override;
  DeviceStatus status() const override { return health_.status(); }

  const serial::DeviceHealth& health() const { return health_; }
  const SickLms2xxLaserOptions& options() const { return options_; }
  double scan_rate_hz() const { return scan_rate_hz_; }

 private:
  class Line;
  struct Exchange;

  void session(serial::SerialPort& port, const std::stop_token& stop);
  void set_up(Line& line);
  std::optional<protocol::sick::StatusReply> probe(Line& line);
  void stream(Line& line);
  void say_goodbye(Line& line);
  // One send of `telegram` and the wait for its reply (`reply_command` or 0x92).
  Exchange exchange(Line& line, std::span<const std::uint8_t> telegram,
                    std::uint8_t reply_command) const;
  // Up to request_tries sends; throws DeviceFault when no reply comes or the reply is 0x92.
  protocol::sick::Telegram request(Line& line, std::span<const std::uint8_t> telegram,
                                   std::uint8_t reply_command, const std::string& what);
  [[noreturn]] void refused(const std::string& why);
  void publish(msgs::LaserScan scan, std::chrono::steady_clock::time_point measured_at);

  SickLms2xxLaserOptions options_;
  double scan_rate_hz_ = 0.0;
  std::size_t values_per_telegram_ = 0;
  serial::DeviceHealth health_{"laser"};
  std::vector<Listener> listeners_;
  // The device thread's own: what the LMS was last known to talk (tried first on a reopen, since
  // an LMS keeps its rate until it is switched off), the range bits of its measuring mode, and
  // the last complaint logged (each is logged once, not at every reopen).
  unsigned last_baud_bps_ = 9600;
  int range_bits_ = 13;
  std::string last_complaint_;
  mutable std::mutex mutex_;
  std::optional<msgs::LaserScan> newest_;
  std::unique_ptr<serial::DeviceThread> thread_;
};

}  // namespace mobot::drivers::hardware
