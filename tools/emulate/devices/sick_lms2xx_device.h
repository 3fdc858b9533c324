#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/geometry/pose2d.h"
#include "drivers/protocol/sick_lms2xx_commands.h"
#include "drivers/protocol/sick_lms2xx_scan.h"
#include "drivers/protocol/sick_lms2xx_telegram.h"
#include "tools/emulate/emulated_device.h"
#include "tools/emulate/emulated_world.h"

namespace mobot::emulate {

// A SICK LMS 200/211/291 on its RS-232 line. It takes the host's telegrams (CRC checked) and
// answers each with ACK and its reply telegram, or with NAK alone when the CRC fails: mode switch
// 0x20 (installation with password, 0x24 all values continuously, 0x25 on request, 0x2A interlaced
// parts continuously, and the baud rates 9600/19200/38400/500000), variant 0x3B (100 or 180 deg;
// 1, 0.5 or 0.25 deg, but not 180 deg at 0.25 deg), status 0x31. Any other command, or a mode it
// does not model, gets ACK and 0x92.
//
// A baud-rate switch is answered at the old rate; the device talks at the new one once that reply
// is out (requested_baud()), and paces every byte at 10 bit times of the current rate. The other
// switches also take effect when their reply is out.
//
// The mirror turns at 75 Hz from power-on (t = 0). In 0x24 a complete scan is ready at the end of
// every rotation at 1 deg, every 2nd at 0.5 deg, every 4th at 0.25 deg (the LMS interlaces the
// rotations); in 0x2A each rotation gives one part of 180 deg at 1 deg steps, offset 0.25 deg times
// 0 (1 deg), 0/2 (0.5 deg) or 0/1/2/3 (0.25 deg) in turn. A scan (or part) goes out only when the
// line is idle the moment it is ready; otherwise it is skipped, so at 38400 baud a 181-value scan
// (372 bytes, 97 ms) goes out every 8th rotation, 9.4 Hz.
//
// Each value is a ray from the mount (the world's base pose composed with mount_in_base) at
// mount_height_m, gaussian noise of range_sigma_m on it, quantised to the units; nothing within
// max_range_m (or the largest code the units can carry) sends the "too far" code. The world is
// read when the scan goes out.
class SickLms2xxDevice final : public EmulatedDevice {
 public:
  struct Options {
    geometry::Pose2D mount_in_base{0.2, 0.0, 0.0};
    double mount_height_m = 0.4;
    double range_sigma_m = 0.01;
    double max_range_m = 80.0;
    std::uint64_t seed = 1;
    protocol::sick::MeasuringUnits units = protocol::sick::MeasuringUnits::kCentimetres;
    // 0: 8 m / 80 m with fields A, B and dazzle, 13-bit ranges (the factory setting).
    std::uint8_t measuring_mode = 0x00;
    int initial_baud = 9600;  // what the LMS talks after power-on
    protocol::sick::Variant initial_variant{protocol::sick::ScanAngle::k180Deg,
                                            protocol::sick::AngularResolution::kHalfDeg};
    protocol::sick::OperatingMode initial_mode = protocol::sick::OperatingMode::kOnRequest;
    std::string password{protocol::sick::kDefaultPassword};
    // From the end of the host's telegram to the ACK.
    double reply_delay_s = 0.002;
    // The status byte of every reply; what the LMS units in published captures send.
    std::uint8_t status = 0x10;
    std::string software_version = "V02.10 ";
  };

  // Throws std::invalid_argument for options an LMS2xx cannot have (a non-finite mount, negative
  // noise or delay, a baud rate it does not talk, a measuring mode without ranges, an unsupported
  // variant or mode).
  explicit SickLms2xxDevice(const EmulatedWorld& world);
  SickLms2xxDevice(const EmulatedWorld& world, Options options);

  std::string_view name() const override { return "sick_lms2xx"; }
  void receive(std::span<const std::uint8_t> bytes, double now_s) override;
  std::vector<std::uint8_t> transmit(double now_s) override;
  void set_bad_checksums(bool on) override { bad_checksums_ = on; }

  // The line rate the LMS talks at: a baud-rate switch changes it once the reply has gone out at
  // the old rate, and the host (or the pty wrapper) has to follow.
  int requested_baud() const { return active_.baud; }
  protocol::sick::OperatingMode operating_mode() const { return active_.mode; }
  protocol::sick::Variant variant() const { return active_.variant; }
  // Scans (or interlaced parts) sent, and skipped because the line was busy.
  std::uint64_t scans_sent() const { return scans_sent_; }
  std::uint64_t scans_skipped() const { return scans_skipped_; }

 private:
  struct Settings {
    protocol::sick::OperatingMode mode = protocol::sick::OperatingMode::kOnRequest;
    protocol::sick::Variant variant;
    int baud = 9600;

    bool operator==(const Settings&) const = default;
  };
  struct Change {
    double at_s = 0.0;
    Settings settings;
  };
  struct Outgoing {
    std::vector<std::uint8_t> bytes;
    double start_s = 0.0;
    double byte_time_s = 0.0;
    std::size_t sent = 0;
    bool telegram = false;  // carries a CRC that set_bad_checksums spoils
  };

  double clamp_time(double now_s);
  // Lets the mirror turn to now_s: the settings changes due by then, and the scans that are ready
  // while the line is idle.
  void advance(double now_s);
  void apply_changes(double until_s);
  void rotation_done(double at_s);
  // Queues bytes on the line from earliest_s or when it is free; returns when they have gone out.
  double queue(std::vector<std::uint8_t> bytes, double earliest_s, bool telegram);
  void answer(const protocol::sick::Telegram& request, double now_s);
  std::vector<std::uint8_t> mode_switch(const std::vector<std::uint8_t>& payload,
                                        Settings& next) const;
  std::vector<std::uint8_t> variant_switch(const std::vector<std::uint8_t>& payload,
                                           Settings& next) const;
  std::vector<std::uint8_t> status() const;
  protocol::sick::MeasuredValues measure(double first_deg, double step_deg, std::size_t count);
  std::uint16_t range_value(const geometry::Pose2D& mount, double angle_rad);

  const EmulatedWorld& world_;
  Options options_;
  int range_bits_ = 13;
  std::mt19937_64 rng_;
  protocol::sick::TelegramStream requests_{protocol::sick::StreamDirection::kToLms};
  bool bad_checksums_ = false;

  double now_s_ = 0.0;
  Settings active_;     // in force at now_s_
  Settings scheduled_;  // in force once every queued reply is out
  std::deque<Change> changes_;
  std::int64_t next_rotation_ = 1;  // rotation k ends at k / 75 s
  std::int64_t streaming_rotations_ = 0;
  std::uint64_t scans_sent_ = 0;
  std::uint64_t scans_skipped_ = 0;

  std::deque<Outgoing> line_;
  double line_free_s_ = 0.0;
};

}  // namespace mobot::emulate
