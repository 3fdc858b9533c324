#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/msgs/laser_scan.h"
#include "drivers/protocol/ydlidar_g4.h"

namespace mobot::protocol::ydlidar {

// The lidar's frame for mobot (the one the mounting pose places on the base) is the ydlidar ROS
// driver's laser frame for the G4, whose settings turn it (reversion) and mirror it (inverted):
// x points away from the cable exit, angles count counter-clockwise. The G4's clockwise angle
// a_deg from its cable is therefore the frame's angle pi - a.
double sensor_angle_rad(double device_angle_deg);
// The inverse, in [0, 360).
double device_angle_deg(double sensor_angle_rad);

// One turn of the head: every sample from a zero packet (CT bit 0) up to the next one.
struct Scan {
  std::vector<Sample> samples;
  // What the next zero packet said of this turn, when the firmware reports it.
  std::optional<double> scan_frequency_hz;
  std::size_t packets = 0;
};

// Groups the packets of the stream into turns. A turn is complete exactly when the zero packet of
// the next one arrives: add() then returns it and starts the next turn with that packet's samples.
// What comes before the first zero packet is a partial turn and is dropped, as is a turn that runs
// past max_samples without a zero packet (a lost one: the turn would span several).
class ScanAssembler {
 public:
  struct Options {
    // A G4 turn holds 9000 / 5 = 1800 samples at its slowest; twice that is surely broken.
    std::size_t max_samples = 3600;
  };

  ScanAssembler() : ScanAssembler(Options{}) {}
  explicit ScanAssembler(Options options) : options_(options) {}

  std::optional<Scan> add(const ScanPacket& packet);
  // Forgets the turn in progress (after a stop, a reconnect): the next zero packet starts afresh.
  void reset();

  std::uint64_t dropped_turns() const { return dropped_turns_; }

 private:
  Options options_;
  Scan current_;
  bool in_turn_ = false;
  std::uint64_t dropped_turns_ = 0;
};

struct LaserScanOptions {
  int bin_count = 720;  // 0.5 degree bins over the full turn
  double range_min_m = 0.10;
  double range_max_m = 16.0;
  geometry::Pose2D sensor_in_base;
};

// A turn as mobot's laser scan: bin_count equal bins over 360 degrees from -pi, beam i at -pi +
// i * 2 pi / bin_count in the frame above. A bin takes the nearest sample within [range_min,
// range_max] that falls in it (nearest: a bin is wider than the gap between samples and an
// obstacle must not vanish behind a farther return). A bin without one is a no-return, out of
// [range_min, range_max], and says which kind:
//   +infinity: the lidar looked and saw nothing within range_max (range 0 from the device, or
//              beyond range_max): free up to the usable range, as mobot's simulator reports it;
//   0:         nothing to say (no sample fell in the bin, or only ones nearer than range_min):
//              below range_min, mobot ignores the beam.
// bin_count < 1 is taken as 1, non-finite or inverted ranges give an all-zero scan.
msgs::LaserScan to_laser_scan(const Scan& scan, const LaserScanOptions& options, double stamp_s);

}  // namespace mobot::protocol::ydlidar
