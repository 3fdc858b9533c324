#include "drivers/protocol/ydlidar_scan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace mobot::protocol::ydlidar {

double sensor_angle_rad(double device_angle_deg) {
  return geometry::wrap_angle(std::numbers::pi - device_angle_deg * std::numbers::pi / 180.0);
}

double device_angle_deg(double sensor_angle_rad) {
  double deg = std::fmod((std::numbers::pi - sensor_angle_rad) * 180.0 / std::numbers::pi, 360.0);
  if (deg < 0.0) deg += 360.0;
  return deg >= 360.0 ? 0.0 : deg;
}

std::optional<Scan> ScanAssembler::add(const ScanPacket& packet) {
  std::optional<Scan> done;
  if (packet.starts_scan()) {
    if (in_turn_) {
      current_.scan_frequency_hz = packet.scan_frequency_hz();
      done = std::move(current_);
    }
    current_ = Scan{};
    in_turn_ = true;
  }
  if (!in_turn_) return done;
  if (current_.samples.size() + packet.samples.size() > options_.max_samples) {
    ++dropped_turns_;
    reset();
    return done;
  }
  current_.samples.insert(current_.samples.end(), packet.samples.begin(), packet.samples.end());
  ++current_.packets;
  return done;
}

void ScanAssembler::reset() {
  current_ = Scan{};
  in_turn_ = false;
}

msgs::LaserScan to_laser_scan(const Scan& scan, const LaserScanOptions& options, double stamp_s) {
  const int bins = std::max(options.bin_count, 1);
  const double increment_rad = 2.0 * std::numbers::pi / bins;
  msgs::LaserScan out;
  out.stamp_s = stamp_s;
  out.angle_min_rad = static_cast<float>(-std::numbers::pi);
  out.angle_increment_rad = static_cast<float>(increment_rad);
  out.range_min_m = static_cast<float>(options.range_min_m);
  out.range_max_m = static_cast<float>(options.range_max_m);
  out.sensor_in_base = options.sensor_in_base;
  out.ranges_m.assign(static_cast<std::size_t>(bins), 0.0F);
  const bool ranges_valid = std::isfinite(options.range_min_m) &&
                            std::isfinite(options.range_max_m) &&
                            options.range_min_m <= options.range_max_m;
  if (!ranges_valid) return out;

  constexpr float kNoReturn = std::numeric_limits<float>::infinity();
  // Per bin: 0 until a sample lands, then +inf (looked, nothing in range) or the nearest return.
  // A float compare orders them: a return always beats +inf, +inf beats nothing.
  std::vector<bool> seen(static_cast<std::size_t>(bins), false);
  for (const Sample& sample : scan.samples) {
    if (!std::isfinite(sample.angle_deg) || !std::isfinite(sample.range_m)) continue;
    const double from_min = sensor_angle_rad(sample.angle_deg) + std::numbers::pi;
    const auto index = static_cast<std::size_t>(std::lround(from_min / increment_rad) % bins);
    float value = 0.0F;
    if (sample.range_m <= 0.0 || sample.range_m > options.range_max_m) {
      value = kNoReturn;
    } else if (sample.range_m >= options.range_min_m) {
      value = static_cast<float>(sample.range_m);
    } else {
      continue;  // nearer than range_min: unreliable, says nothing
    }
    float& bin = out.ranges_m[index];
    bin = seen[index] ? std::min(bin, value) : value;
    seen[index] = true;
  }
  return out;
}

}  // namespace mobot::protocol::ydlidar
