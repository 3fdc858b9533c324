#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <random>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "core/geometry/pose2d.h"
#include "drivers/protocol/ydlidar_g4.h"
#include "tools/emulate/emulated_device.h"
#include "tools/emulate/emulated_world.h"

namespace mobot::emulate {

// A YDLIDAR G4 on its serial line. Idle, it answers device info (A5 90), health (A5 92, or the
// manual's A5 91), the scan frequency (A5 0D, and the steps A5 09/0A/0B/0C) and the sampling rate
// (A5 D1). Start scan (A5 60/61) answers A5 5A 05 00 00 40 81 and the packets follow: the samples
// are taken at the sampling rate as the head turns at the scan rate, a zero packet (CT bit 0, one
// sample, CT >> 1 the frequency in 1/10 Hz) opens each turn and the others carry up to
// samples_per_packet. A packet leaves once its last sample is taken, and the line carries one
// byte per 10 bit times at most. While it scans, the G4 takes nothing but stop (A5 65, or the
// SDK's A5 00 before it); restart (A5 40, the SDK's A5 80) stops it and answers nothing.
//
// Each sample is a ray from the lidar (the base pose of the world composed with the mounting
// pose) at height_m, in the direction of its corrected angle, with gaussian noise of sigma
// max(0.01 m, 0.005 * range); nothing within max_range_m, or a range short of min_range_m, is
// distance 0. The world is read when transmit() takes the samples, so a caller that moves the base
// between calls sees it move in the scan.
class YdlidarG4Device final : public EmulatedDevice {
 public:
  struct Options {
    geometry::Pose2D mounting_pose;  // the lidar frame of protocol/ydlidar_scan.h, on the base
    double height_m = 0.2;
    double scan_rate_hz = 7.0;    // 5..12, as the G4's motor control allows
    int sampling_rate_hz = 9000;  // 4000, 8000 or 9000
    std::size_t samples_per_packet = 40;
    // The plain G4 sends distances only. The intensity format needs 3 bytes a sample, which the
    // line carries only at the lower sampling rates.
    protocol::ydlidar::SampleFormat format = protocol::ydlidar::SampleFormat::kDistance;
    double min_range_m = 0.10;
    double max_range_m = 16.0;
    int baud_rate = protocol::ydlidar::kBaudRate;
    std::uint64_t seed = 1;
    protocol::ydlidar::DeviceInfo info{
        protocol::ydlidar::kG4ModelCode, 1, 2, 1, {2, 0, 2, 0, 0, 6, 1, 5, 0, 0, 0, 2, 0, 0, 0, 7}};
    protocol::ydlidar::Health health;
  };

  // Throws std::invalid_argument for options the G4 cannot have, or a data rate its line cannot
  // carry.
  YdlidarG4Device(const EmulatedWorld& world, Options options);

  std::string_view name() const override { return "ydlidar_g4"; }
  void receive(std::span<const std::uint8_t> bytes, double now_s) override;
  std::vector<std::uint8_t> transmit(double now_s) override;
  void set_bad_checksums(bool on) override { bad_checksums_ = on; }

  bool scanning() const { return scanning_; }
  double scan_rate_hz() const { return scan_rate_hz_; }

  // For latency tracing: called with the output offset just past the last byte (bytes transmit()
  // has returned since construction, that byte included) of each packet that completes a turn.
  // That is the zero packet opening the next turn, the packet with which a host's assembler can
  // give the turn out; the first zero packet of a scan completes none. Unset: nothing is called.
  using TurnEndHook = std::function<void(std::uint64_t end_offset)>;
  void set_turn_end_hook(TurnEndHook hook) { turn_end_hook_ = std::move(hook); }

 private:
  struct Frame {
    double ready_s = 0.0;  // when the device has it ready to send
    std::vector<std::uint8_t> bytes;
    std::size_t sent = 0;
    bool scan_data = false;
    bool ends_turn = false;  // a zero packet after which the host can close the previous turn
  };

  // Takes the samples due by now_s and lets the line send what it can by then.
  void advance(double now_s);
  void take_samples(double now_s);
  void send_line(double now_s);
  void close_packet();
  protocol::ydlidar::RawSample measure(double raw_angle_deg);
  // Distance along the G4 angle `angle_deg` from the lidar, 0 for no hit.
  double cast_mm(const geometry::Pose2D& lidar, double angle_deg) const;
  void handle(std::uint8_t command, double now_s);
  void start_scan(double now_s);
  void stop_scan();
  void queue_response(const protocol::ydlidar::ResponseHeader& header,
                      std::span<const std::uint8_t> payload, double now_s);
  void queue_scan_frequency(double now_s);

  const EmulatedWorld& world_;
  Options options_;
  double byte_time_s_ = 0.0;
  double scan_rate_hz_ = 0.0;
  std::mt19937_64 rng_;
  bool bad_checksums_ = false;

  double now_s_ = 0.0;
  bool pending_sync_ = false;  // an A5 came, its command byte not yet

  bool scanning_ = false;
  double scan_start_s_ = 0.0;
  std::uint64_t next_sample_ = 0;  // index of the next sample since the scan started
  double last_distance_mm_ = 0.0;  // the previous sample's, a first guess for the next
  std::vector<protocol::ydlidar::RawSample> packet_;
  double packet_first_deg_ = 0.0;
  double packet_last_deg_ = 0.0;
  double packet_ready_s_ = 0.0;
  bool packet_is_zero_ = false;
  bool turn_open_ = false;  // a zero packet of this scan has gone to the line

  std::deque<Frame> line_;
  double line_free_s_ = 0.0;  // when the line has sent what it was given
  std::vector<std::uint8_t> outbox_;
  std::uint64_t transmitted_bytes_ = 0;  // returned by transmit() so far
  TurnEndHook turn_end_hook_;
};

}  // namespace mobot::emulate
