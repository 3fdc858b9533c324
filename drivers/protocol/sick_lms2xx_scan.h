#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/msgs/laser_scan.h"
#include "drivers/protocol/sick_lms2xx_commands.h"
#include "drivers/protocol/sick_lms2xx_telegram.h"

namespace mobot::protocol::sick {

// The measured-values telegram 0xB0, as the LMS streams it in modes 0x24 and 0x2A:
//   0xB0 | value count word (2 bytes) | values (2 bytes each) | [real-time index] | status
// Count word: bits 0-9 the number of values, bits 11-12 the partial-scan index (the part's
// offset in 0.25 deg), bit 13 set for a part of an interlaced scan, bits 14-15 the units
// (0 cm, 1 mm). Each value: the range in its low bits, flag bits (fields, reflector, dazzle)
// above them; how many low bits depends on the measuring mode (13 in the factory 8 m / 80 m
// mode). The real-time index is only there when the availability setting asks for it.
// Value 0 of a scan is the beam on the right (-90 deg, or -50 deg at 100 deg); the angle grows
// counter-clockwise.
inline constexpr std::size_t kMaxValues = 721;

// Low bits that carry the range for a measuring mode (status reply byte): 13 for the 8 m / 80 m
// modes 0-2, 14 for the 16 m modes 3-4, 15 for the 32 m modes 5-6, 16 for 0x0F (no flags);
// 0 for modes that do not send ranges (0x3F: reflectivity) or that are unknown.
int range_bits_for_measuring_mode(std::uint8_t measuring_mode);

// The top codes of the range field are not ranges. For 13 bits: 8191 not valid, 8190 dazzled,
// 8189 operation overflow, 8187 signal-to-noise too low, 8186 error reading channel 1, 8183
// measured value above the maximum (no target within range); likewise below 2^bits - 1 for the
// other widths. Every code from 2^bits - 9 up is treated as "no return".
enum class RangeError { kTooFar, kChannelError, kLowSignal, kOverflow, kDazzled, kNotValid };
std::uint16_t range_error_code(RangeError error, int range_bits);
// The largest code that is a range.
std::uint16_t max_range_code(int range_bits);
std::uint16_t range_code(std::uint16_t value, int range_bits);
std::uint16_t flag_bits(std::uint16_t value, int range_bits);  // the bits above the range

struct MeasuredValues {
  MeasuringUnits units = MeasuringUnits::kCentimetres;
  bool partial_scan = false;  // one part of an interlaced scan (mode 0x2A)
  int partial_index = 0;      // 0..3: the part starts 0.25 deg * partial_index past the first beam
  std::vector<std::uint16_t> values;  // as sent: range code and flag bits
  // The LMS appends it only when configured to. Encoded as one byte.
  std::optional<std::uint16_t> real_time_index;
  std::uint8_t status = 0;

  bool operator==(const MeasuredValues&) const = default;
};

// nullopt unless `telegram` is a well-formed 0xB0: at most 721 values, units cm or mm, and a
// payload length that matches the count (with 0, 1 or 2 bytes of real-time index).
std::optional<MeasuredValues> decode_measured_values(const Telegram& telegram);
// The complete 0xB0 telegram from kReplyAddress. At most kMaxValues values are sent.
std::vector<std::uint8_t> measured_values_telegram(const MeasuredValues& values);

// Builds a complete 0.5 or 0.25 deg scan from the parts the LMS sends in mode 0x2A, one per
// mirror rotation: part 0 has the beams at whole degrees (181 values over 180 deg, 101 over
// 100 deg), part k the beams 0.25 deg * k further on (one value fewer, the last one would lie
// outside the field of view). 0.5 deg takes parts 0 and 2, 0.25 deg parts 0 to 3. A scan is
// given out when the most recent parts — as many as the resolution needs, in any order, since a
// slow line makes the LMS skip rotations — cover every offset. A telegram that is no part of
// this resolution is dropped; a complete (non-partial) scan passes through unchanged.
class InterlacedScanAssembler {
 public:
  explicit InterlacedScanAssembler(AngularResolution resolution);

  std::optional<MeasuredValues> add(const MeasuredValues& values);
  void reset();

 private:
  int parts_needed_;
  std::vector<std::optional<MeasuredValues>> parts_;  // by part number (partial_index / step)
  std::vector<std::uint64_t> received_at_;            // ordinal of the add() that stored it
  std::uint64_t ordinal_ = 0;
};

struct LaserScanOptions {
  double stamp_s = 0.0;
  geometry::Pose2D sensor_in_base{0.2, 0.0, 0.0};
  double range_min_m = 0.4;
  // Clipped to the largest range the units and range bits can carry (81.82 m in cm, 8.182 m in
  // mm with 13 bits).
  double range_max_m = 80.0;
  int range_bits = 13;  // range_bits_for_measuring_mode of the LMS's measuring mode
};

// The scan in the sensor frame: beam 0 at -90 deg (-50 deg at 100 deg), increments from the value
// count (181, 361, 721 over 180 deg; 101, 201, 401 over 100 deg; a single interlaced part at
// 1 deg from its offset). Error codes read range_max_m + 1 m, "no return". nullopt for a count
// that fits no variant or an unusable range_bits.
std::optional<msgs::LaserScan> to_laser_scan(const MeasuredValues& values,
                                             const LaserScanOptions& options);

}  // namespace mobot::protocol::sick
