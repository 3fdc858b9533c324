#include "drivers/protocol/sick_lms2xx_scan.h"

#include <algorithm>
#include <numbers>

namespace mobot::protocol::sick {
namespace {

constexpr std::uint16_t kCountMask = 0x03FF;
constexpr int kPartialIndexShift = 11;
constexpr std::uint16_t kPartialScanBit = 0x2000;
constexpr int kUnitsShift = 14;
// Offsets of the error codes below the all-ones code of the range field.
constexpr std::uint16_t kTooFarBelowTop = 8;
constexpr int kQuarterStepsPerDegree = 4;
// Where mobot's scans put "no return": past range_max_m, by as much as the simulator's.
constexpr double kNoReturnBeyondMax_m = 1.0;

bool usable_range_bits(int range_bits) { return range_bits >= 13 && range_bits <= 16; }

std::uint16_t all_ones(int range_bits) {
  return static_cast<std::uint16_t>((1U << static_cast<unsigned>(range_bits)) - 1U);
}

double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

struct ScanGeometry {
  double first_deg = 0.0;
  double step_deg = 0.0;
};

// Field of view of an interlaced part from its count: part 0 has one value more than the others.
std::optional<int> part_field_of_view_deg(std::size_t count, int partial_index) {
  for (const int fov_deg : {100, 180}) {
    const std::size_t expected = static_cast<std::size_t>(fov_deg) + (partial_index == 0 ? 1 : 0);
    if (count == expected) return fov_deg;
  }
  return std::nullopt;
}

std::optional<ScanGeometry> geometry_of(const MeasuredValues& values) {
  const std::size_t count = values.values.size();
  if (values.partial_scan) {
    const std::optional<int> fov_deg = part_field_of_view_deg(count, values.partial_index);
    if (!fov_deg) return std::nullopt;
    return ScanGeometry{-*fov_deg / 2.0 + 0.25 * values.partial_index, 1.0};
  }
  for (const int fov_deg : {100, 180}) {
    for (const double step_deg : {1.0, 0.5, 0.25}) {
      if (count == static_cast<std::size_t>(fov_deg / step_deg) + 1) {
        return ScanGeometry{-fov_deg / 2.0, step_deg};
      }
    }
  }
  return std::nullopt;
}

}  // namespace

int range_bits_for_measuring_mode(std::uint8_t measuring_mode) {
  switch (measuring_mode) {
    case 0x00:
    case 0x01:
    case 0x02:
      return 13;
    case 0x03:
    case 0x04:
      return 14;
    case 0x05:
    case 0x06:
      return 15;
    case 0x0F:
      return 16;
    default:
      return 0;
  }
}

std::uint16_t range_error_code(RangeError error, int range_bits) {
  const std::uint16_t top = all_ones(std::clamp(range_bits, 13, 16));
  std::uint16_t below = 0;
  switch (error) {
    case RangeError::kTooFar:
      below = kTooFarBelowTop;
      break;
    case RangeError::kChannelError:
      below = 5;
      break;
    case RangeError::kLowSignal:
      below = 4;
      break;
    case RangeError::kOverflow:
      below = 2;
      break;
    case RangeError::kDazzled:
      below = 1;
      break;
    case RangeError::kNotValid:
      below = 0;
      break;
  }
  return static_cast<std::uint16_t>(top - below);
}

std::uint16_t max_range_code(int range_bits) {
  return static_cast<std::uint16_t>(range_error_code(RangeError::kTooFar, range_bits) - 1U);
}

std::uint16_t range_code(std::uint16_t value, int range_bits) {
  return static_cast<std::uint16_t>(value & all_ones(std::clamp(range_bits, 13, 16)));
}

std::uint16_t flag_bits(std::uint16_t value, int range_bits) {
  return static_cast<std::uint16_t>(value & ~all_ones(std::clamp(range_bits, 13, 16)));
}

std::optional<MeasuredValues> decode_measured_values(const Telegram& telegram) {
  const std::vector<std::uint8_t>& p = telegram.payload;
  if (p.size() < 4 || p[0] != kMeasuredValuesReply) return std::nullopt;
  const auto word = static_cast<std::uint16_t>(p[1] | (p[2] << 8U));
  const std::size_t count = word & kCountMask;
  const unsigned units = static_cast<unsigned>(word) >> kUnitsShift;
  if (count > kMaxValues || units > 1U) return std::nullopt;
  const std::size_t least = 1 + 2 + 2 * count + 1;
  if (p.size() < least || p.size() > least + 2) return std::nullopt;

  MeasuredValues values;
  values.units = units == 1U ? MeasuringUnits::kMillimetres : MeasuringUnits::kCentimetres;
  values.partial_scan = (word & kPartialScanBit) != 0;
  values.partial_index = (word >> kPartialIndexShift) & 0x3;
  values.values.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    values.values.push_back(static_cast<std::uint16_t>(p[3 + 2 * i] | (p[4 + 2 * i] << 8U)));
  }
  const std::size_t index_bytes = p.size() - least;
  if (index_bytes == 1) {
    values.real_time_index = p[least - 1];
  } else if (index_bytes == 2) {
    values.real_time_index = static_cast<std::uint16_t>(p[least - 1] | (p[least] << 8U));
  }
  values.status = p.back();
  return values;
}

std::vector<std::uint8_t> measured_values_telegram(const MeasuredValues& values) {
  const std::size_t count = std::min(values.values.size(), kMaxValues);
  auto word = static_cast<std::uint16_t>(count);
  word = static_cast<std::uint16_t>(word | ((values.partial_index & 0x3) << kPartialIndexShift));
  if (values.partial_scan) word = static_cast<std::uint16_t>(word | kPartialScanBit);
  word = static_cast<std::uint16_t>(word | (static_cast<unsigned>(values.units) << kUnitsShift));

  std::vector<std::uint8_t> payload;
  payload.reserve(1 + 2 + 2 * count + 2);
  payload.push_back(kMeasuredValuesReply);
  payload.push_back(static_cast<std::uint8_t>(word & 0xFFU));
  payload.push_back(static_cast<std::uint8_t>(word >> 8U));
  for (std::size_t i = 0; i < count; ++i) {
    payload.push_back(static_cast<std::uint8_t>(values.values[i] & 0xFFU));
    payload.push_back(static_cast<std::uint8_t>(values.values[i] >> 8U));
  }
  if (values.real_time_index) {
    payload.push_back(static_cast<std::uint8_t>(*values.real_time_index & 0xFFU));
  }
  payload.push_back(values.status);
  return encode_telegram(kReplyAddress, payload);
}

InterlacedScanAssembler::InterlacedScanAssembler(AngularResolution resolution)
    : parts_needed_(rotations_per_scan(resolution)),
      parts_(static_cast<std::size_t>(parts_needed_)),
      received_at_(static_cast<std::size_t>(parts_needed_), 0) {}

void InterlacedScanAssembler::reset() { std::fill(parts_.begin(), parts_.end(), std::nullopt); }

std::optional<MeasuredValues> InterlacedScanAssembler::add(const MeasuredValues& values) {
  if (!values.partial_scan) return values;
  const int step = kQuarterStepsPerDegree / parts_needed_;
  if (values.partial_index % step != 0) return std::nullopt;
  const std::optional<int> fov_deg =
      part_field_of_view_deg(values.values.size(), values.partial_index);
  if (!fov_deg) return std::nullopt;

  ++ordinal_;
  const auto part = static_cast<std::size_t>(values.partial_index / step);
  // A part from another field of view or in other units cannot join the stored ones.
  for (const std::optional<MeasuredValues>& other : parts_) {
    if (other && (other->units != values.units ||
                  part_field_of_view_deg(other->values.size(), other->partial_index) != fov_deg)) {
      reset();
      break;
    }
  }
  parts_[part] = values;
  received_at_[part] = ordinal_;
  const auto window = static_cast<std::uint64_t>(parts_needed_);
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    if (!parts_[i] || ordinal_ - received_at_[i] >= window) return std::nullopt;
  }

  MeasuredValues scan;
  scan.units = values.units;
  scan.status = values.status;
  scan.real_time_index = values.real_time_index;
  const auto parts = static_cast<std::size_t>(parts_needed_);
  const auto degrees = static_cast<std::size_t>(*fov_deg);
  scan.values.assign(degrees * parts + 1, 0);
  for (std::size_t k = 0; k < parts; ++k) {
    const std::vector<std::uint16_t>& part_values = parts_[k]->values;
    for (std::size_t j = 0; j < part_values.size(); ++j) {
      scan.values[j * parts + k] = part_values[j];
    }
  }
  reset();
  return scan;
}

std::optional<msgs::LaserScan> to_laser_scan(const MeasuredValues& values,
                                             const LaserScanOptions& options) {
  if (!usable_range_bits(options.range_bits)) return std::nullopt;
  const std::optional<ScanGeometry> geometry = geometry_of(values);
  if (!geometry) return std::nullopt;

  const double metres = metres_per_unit(values.units);
  const std::uint16_t largest = max_range_code(options.range_bits);
  const double range_max_m = std::min(options.range_max_m, largest * metres);
  const double no_return_m = range_max_m + kNoReturnBeyondMax_m;

  msgs::LaserScan scan;
  scan.stamp_s = options.stamp_s;
  scan.angle_min_rad = static_cast<float>(radians(geometry->first_deg));
  scan.angle_increment_rad = static_cast<float>(radians(geometry->step_deg));
  scan.range_min_m = static_cast<float>(options.range_min_m);
  scan.range_max_m = static_cast<float>(range_max_m);
  scan.sensor_in_base = options.sensor_in_base;
  scan.ranges_m.reserve(values.values.size());
  for (const std::uint16_t value : values.values) {
    const std::uint16_t code = range_code(value, options.range_bits);
    scan.ranges_m.push_back(static_cast<float>(code > largest ? no_return_m : code * metres));
  }
  return scan;
}

}  // namespace mobot::protocol::sick
