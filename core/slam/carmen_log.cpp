#include "core/slam/carmen_log.h"

#include <charconv>
#include <cmath>
#include <numbers>

namespace mobot::slam {

namespace {

constexpr std::size_t kMaxBeams = 10000;

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
  return fields;
}

bool to_double(std::string_view field, double& value) {
  const char* end = field.data() + field.size();
  const auto result = std::from_chars(field.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

CarmenLine malformed(std::string error) {
  CarmenLine out;
  out.kind = CarmenLine::Kind::kMalformed;
  out.error = std::move(error);
  return out;
}

// Reads fields[index..index+count) as numbers into `values`; false on the first bad one.
bool read_numbers(const std::vector<std::string_view>& fields, std::size_t index, std::size_t count,
                  std::vector<double>& values, std::string& error) {
  values.clear();
  for (std::size_t k = 0; k < count; ++k) {
    double v = 0.0;
    if (!to_double(fields[index + k], v)) {
      error = "field " + std::to_string(index + k + 1) + " is not a number: '" +
              std::string(fields[index + k]) + "'";
      return false;
    }
    values.push_back(v);
  }
  return true;
}

bool read_beam_count(std::string_view field, std::size_t& count, std::string& error) {
  double n = 0.0;
  if (!to_double(field, n) || n != std::floor(n) || n < 1.0 || n > static_cast<double>(kMaxBeams)) {
    error = "beam count '" + std::string(field) + "' is not an integer in 1.." +
            std::to_string(kMaxBeams);
    return false;
  }
  count = static_cast<std::size_t>(n);
  return true;
}

CarmenLine parse_flaser(const std::vector<std::string_view>& fields) {
  std::string error;
  if (fields.size() < 2) return malformed("FLASER without a beam count");
  std::size_t n = 0;
  if (!read_beam_count(fields[1], n, error)) return malformed(error);
  // n ranges, 6 pose values and the timestamp; host and logger time may be missing.
  if (fields.size() < 2 + n + 7) {
    return malformed("FLASER with " + std::to_string(n) + " beams needs at least " +
                     std::to_string(n + 9) + " fields, has " + std::to_string(fields.size()));
  }
  std::vector<double> values;
  if (!read_numbers(fields, 2, n + 7, values, error)) return malformed(error);
  CarmenLaser laser;
  laser.ranges_m.reserve(n);
  for (std::size_t i = 0; i < n; ++i) laser.ranges_m.push_back(static_cast<float>(values[i]));
  laser.laser_pose = {values[n], values[n + 1], values[n + 2]};
  laser.odom_pose = {values[n + 3], values[n + 4], values[n + 5]};
  laser.timestamp_s = values[n + 6];
  laser.angle_min_rad = static_cast<float>(-std::numbers::pi / 2.0);
  laser.angle_increment_rad = static_cast<float>(flaser_angle_increment_rad(n));
  if (!geometry::is_finite(laser.laser_pose) || !geometry::is_finite(laser.odom_pose) ||
      !std::isfinite(laser.timestamp_s)) {
    return malformed("FLASER with a non-finite pose or timestamp");
  }
  CarmenLine out;
  out.kind = CarmenLine::Kind::kLaser;
  out.laser = std::move(laser);
  return out;
}

// ROBOTLASER1 type start_angle fov resolution max_range accuracy remission_mode n r_1..r_n
// m rem_1..rem_m laser_x y theta robot_x y theta tv rv fwd_safety side_safety turn_axis timestamp
// host logger_timestamp
CarmenLine parse_robotlaser1(const std::vector<std::string_view>& fields) {
  std::string error;
  if (fields.size() < 9) return malformed("ROBOTLASER1 with too few fields");
  std::vector<double> header;
  if (!read_numbers(fields, 1, 7, header, error)) return malformed(error);
  std::size_t n = 0;
  if (!read_beam_count(fields[8], n, error)) return malformed(error);
  const std::size_t remissions_at = 9 + n;
  if (fields.size() <= remissions_at) return malformed("ROBOTLASER1 truncated in its ranges");
  double m = 0.0;
  if (!to_double(fields[remissions_at], m) || m < 0.0 || m != std::floor(m) ||
      m > static_cast<double>(kMaxBeams)) {
    return malformed("ROBOTLASER1 with a bad remission count");
  }
  const std::size_t tail_at = remissions_at + 1 + static_cast<std::size_t>(m);
  if (fields.size() < tail_at + 12) return malformed("ROBOTLASER1 truncated after its ranges");
  std::vector<double> ranges;
  if (!read_numbers(fields, 9, n, ranges, error)) return malformed(error);
  std::vector<double> tail;
  if (!read_numbers(fields, tail_at, 12, tail, error)) return malformed(error);
  CarmenLaser laser;
  laser.angle_min_rad = static_cast<float>(header[1]);
  laser.angle_increment_rad = static_cast<float>(header[3]);
  laser.range_max_m = static_cast<float>(header[4]);
  laser.ranges_m.reserve(n);
  for (double r : ranges) laser.ranges_m.push_back(static_cast<float>(r));
  laser.laser_pose = {tail[0], tail[1], tail[2]};
  laser.odom_pose = {tail[3], tail[4], tail[5]};
  laser.timestamp_s = tail[11];
  if (!geometry::is_finite(laser.laser_pose) || !geometry::is_finite(laser.odom_pose) ||
      !std::isfinite(laser.timestamp_s) || !std::isfinite(header[1]) || !std::isfinite(header[3])) {
    return malformed("ROBOTLASER1 with a non-finite pose, angle or timestamp");
  }
  CarmenLine out;
  out.kind = CarmenLine::Kind::kLaser;
  out.laser = std::move(laser);
  return out;
}

}  // namespace

double flaser_angle_increment_rad(std::size_t beam_count) {
  if (beam_count < 2) return std::numbers::pi;
  const std::size_t steps = beam_count % 2 == 1 ? beam_count - 1 : beam_count;
  return std::numbers::pi / static_cast<double>(steps);
}

CarmenLine parse_carmen_line(std::string_view line) {
  const std::vector<std::string_view> fields = split_fields(line);
  if (fields.empty() || fields[0].front() == '#') return {};
  if (fields[0] == "FLASER") return parse_flaser(fields);
  if (fields[0] == "ROBOTLASER1") return parse_robotlaser1(fields);
  return {};
}

msgs::LaserScan to_laser_scan(const CarmenLaser& laser, double no_return_range_m,
                              const geometry::Pose2D& sensor_in_base) {
  msgs::LaserScan scan;
  scan.stamp_s = laser.timestamp_s;
  scan.angle_min_rad = laser.angle_min_rad;
  scan.angle_increment_rad = laser.angle_increment_rad;
  scan.range_min_m = 0.0F;
  scan.range_max_m =
      laser.range_max_m > 0.0F ? laser.range_max_m : static_cast<float>(no_return_range_m);
  scan.sensor_in_base = sensor_in_base;
  scan.ranges_m = laser.ranges_m;
  return scan;
}

}  // namespace mobot::slam
