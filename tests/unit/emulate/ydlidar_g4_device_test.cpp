#include "tools/emulate/devices/ydlidar_g4_device.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <stdexcept>
#include <variant>
#include <vector>

#include "drivers/protocol/ydlidar_g4.h"
#include "drivers/protocol/ydlidar_scan.h"
#include "drivers/protocol/ydlidar_stream_parser.h"

namespace mobot::emulate {
namespace {

namespace yd = protocol::ydlidar;

// A round room of radius 2 m centred on the origin, optionally with a wall along y = wall_y_m
// that only rays heading to +y reach (it tells left from right).
class RoundRoom final : public EmulatedWorld {
 public:
  explicit RoundRoom(std::optional<double> wall_y_m = std::nullopt) : wall_y_m_(wall_y_m) {}

  geometry::Pose2D base_pose() const override { return pose_; }
  void set_base_pose(const geometry::Pose2D& pose) override { pose_ = pose; }

  std::optional<double> cast_ray(geometry::Point2D from, double angle_rad, double height_m,
                                 double max_range_m) const override {
    last_height_m = height_m;
    const double dx = std::cos(angle_rad);
    const double dy = std::sin(angle_rad);
    std::optional<double> hit_m;
    if (wall_y_m_) {
      if (dy > 1e-9 && *wall_y_m_ > from.y) hit_m = (*wall_y_m_ - from.y) / dy;
    } else {
      // |from + t d| = R, from inside: the positive root.
      const double b = from.x * dx + from.y * dy;
      const double c = from.x * from.x + from.y * from.y - kRadius_m * kRadius_m;
      hit_m = -b + std::sqrt(b * b - c);
    }
    if (hit_m && *hit_m > max_range_m) return std::nullopt;
    return hit_m;
  }

  static constexpr double kRadius_m = 2.0;
  mutable double last_height_m = 0.0;

 private:
  std::optional<double> wall_y_m_;
  geometry::Pose2D pose_;
};

// The host side: what a driver would run on the bytes.
struct Host {
  explicit Host(yd::SampleFormat format = yd::SampleFormat::kDistance) : parser({format}) {}

  void take(const std::vector<std::uint8_t>& bytes, double now_s) {
    std::vector<yd::StreamItem> items;
    parser.feed(bytes, items);
    for (yd::StreamItem& item : items) {
      if (auto* response = std::get_if<yd::Response>(&item)) {
        responses.push_back(std::move(*response));
      } else if (auto turn = assembler.add(std::get<yd::ScanPacket>(item))) {
        scans.push_back(std::move(*turn));
        scan_times_s.push_back(now_s);
      }
    }
  }

  yd::StreamParser parser;
  yd::ScanAssembler assembler;
  std::vector<yd::Response> responses;
  std::vector<yd::Scan> scans;
  std::vector<double> scan_times_s;
};

void send(YdlidarG4Device& device, yd::Command command, double now_s) {
  const auto bytes = yd::encode_command(command);
  device.receive(bytes, now_s);
}

// Runs the device from from_s to to_s in steps of step_s, feeding the host; returns the largest
// number of bytes one step brought.
std::size_t run(YdlidarG4Device& device, Host& host, double from_s, double to_s,
                double step_s = 0.01) {
  std::size_t most = 0;
  const auto steps = static_cast<int>(std::lround((to_s - from_s) / step_s));
  for (int i = 1; i <= steps; ++i) {
    const double now_s = from_s + i * step_s;
    const auto bytes = device.transmit(now_s);
    most = std::max(most, bytes.size());
    host.take(bytes, now_s);
  }
  return most;
}

TEST(YdlidarG4Device, AnswersDeviceInfoAndHealth) {
  RoundRoom room;
  YdlidarG4Device::Options options;
  options.health = {1, 0x0203};
  YdlidarG4Device device(room, options);
  Host host;
  EXPECT_TRUE(device.transmit(0.5).empty());  // idle and unasked: silent
  send(device, yd::Command::kGetDeviceInfo, 1.0);
  // The manual's health code and the SDK's.
  send(device, yd::Command::kGetHealthManual, 1.0);
  send(device, yd::Command::kGetHealth, 1.0);
  send(device, yd::Command::kGetScanFrequency, 1.0);
  send(device, yd::Command::kGetSamplingRate, 1.0);
  // 27 + 10 + 10 + 11 + 8 bytes take 66 byte times, 2.9 ms at 230400 baud.
  const auto early = device.transmit(1.001);
  EXPECT_LT(early.size(), 66U);
  host.take(early, 1.001);
  host.take(device.transmit(1.0029), 1.0029);
  ASSERT_EQ(host.responses.size(), 5U);
  const auto info = yd::decode_device_info(host.responses[0].payload);
  ASSERT_TRUE(info.has_value());
  EXPECT_EQ(*info, options.info);
  EXPECT_EQ(info->model, yd::kG4ModelCode);
  for (int i : {1, 2}) {
    EXPECT_EQ(host.responses[i].header.type, yd::kTypeHealth);
    EXPECT_EQ(yd::decode_health(host.responses[i].payload), options.health);
  }
  EXPECT_DOUBLE_EQ(*yd::decode_scan_frequency_hz(host.responses[3].payload), 7.0);
  EXPECT_EQ(*yd::decode_sampling_rate_hz(host.responses[4].payload), 9000);
  EXPECT_EQ(host.parser.stats().discarded_bytes, 0U);
}

TEST(YdlidarG4Device, ACommandMaySplitAcrossWrites) {
  RoundRoom room;
  YdlidarG4Device device(room, {});
  Host host;
  const std::uint8_t a5 = 0xA5;
  const std::uint8_t info = 0x90;
  device.receive(std::span(&a5, 1), 0.0);
  device.receive(std::span(&info, 1), 0.01);
  host.take(device.transmit(0.1), 0.1);
  ASSERT_EQ(host.responses.size(), 1U);
  EXPECT_EQ(host.responses[0].header.type, yd::kTypeDeviceInfo);
}

TEST(YdlidarG4Device, ScansAtSevenHertzAtTheRightByteRate) {
  RoundRoom room;
  YdlidarG4Device device(room, {});
  Host host;
  send(device, yd::Command::kStartScan, 0.0);
  const std::size_t most_per_step = run(device, host, 0.0, 10.0);
  ASSERT_FALSE(host.responses.empty());
  EXPECT_EQ(host.responses[0].header,
            (yd::ResponseHeader{5, yd::ResponseMode::kContinuous, yd::kTypeScan}));
  EXPECT_TRUE(device.scanning());

  // The first turn starts at 0 s; each completes when the next zero packet is through.
  ASSERT_GE(host.scans.size(), 68U);
  ASSERT_LE(host.scans.size(), 70U);
  for (std::size_t i = 1; i < host.scan_times_s.size(); ++i) {
    EXPECT_NEAR(host.scan_times_s[i] - host.scan_times_s[i - 1], 1.0 / 7.0, 0.011) << i;
  }
  const double mean_period_s = (host.scan_times_s.back() - host.scan_times_s.front()) /
                               static_cast<double>(host.scan_times_s.size() - 1);
  EXPECT_NEAR(mean_period_s, 1.0 / 7.0, 0.001);

  for (const yd::Scan& scan : host.scans) {
    // 9000 / 7 = 1285.7 samples a turn.
    EXPECT_GE(scan.samples.size(), 1285U);
    EXPECT_LE(scan.samples.size(), 1286U);
    ASSERT_TRUE(scan.scan_frequency_hz.has_value());
    EXPECT_DOUBLE_EQ(*scan.scan_frequency_hz, 7.0);
  }

  // 9000 samples of 2 bytes and 9000 / 40 + 14 headers of 10 bytes a second: 20390 bytes/s,
  // below the 23040 bytes/s of 230400 baud. No 10 ms step ever brings more than the line carries.
  const double bytes_per_s = static_cast<double>(host.parser.stats().bytes) / 10.0;
  EXPECT_NEAR(bytes_per_s, 20390.0, 150.0);
  EXPECT_LE(most_per_step, 231U);
  EXPECT_EQ(host.parser.stats().checksum_errors, 0U);
  EXPECT_EQ(host.parser.stats().discarded_bytes, 0U);
  EXPECT_DOUBLE_EQ(room.last_height_m, 0.2);
}

TEST(YdlidarG4Device, RangesAreTheRoomsRadiusWithTheRightNoise) {
  RoundRoom room;
  YdlidarG4Device device(room, {});
  Host host;
  send(device, yd::Command::kStartScan, 0.0);
  run(device, host, 0.0, 2.0);
  ASSERT_GE(host.scans.size(), 10U);
  double sum_m = 0.0;
  double sum_sq_m2 = 0.0;
  std::size_t count = 0;
  for (const yd::Scan& scan : host.scans) {
    for (const yd::Sample& sample : scan.samples) {
      // sigma = max(0.01, 0.005 * 2) = 0.01 m; the wire keeps 0.25 mm.
      EXPECT_NEAR(sample.range_m, 2.0, 0.06);
      sum_m += sample.range_m;
      sum_sq_m2 += (sample.range_m - 2.0) * (sample.range_m - 2.0);
      ++count;
    }
  }
  EXPECT_NEAR(sum_m / static_cast<double>(count), 2.0, 0.002);
  EXPECT_NEAR(std::sqrt(sum_sq_m2 / static_cast<double>(count)), 0.01, 0.001);

  const msgs::LaserScan laser = yd::to_laser_scan(host.scans.back(), {}, 2.0);
  for (const float range_m : laser.ranges_m) EXPECT_NEAR(range_m, 2.0F, 0.06F);
}

// The range seen by the beam of `laser` nearest to `angle_rad`.
float range_at(const msgs::LaserScan& laser, double angle_rad) {
  const double from_min = geometry::wrap_angle(angle_rad) - laser.angle_min_rad;
  const auto bins = static_cast<long>(laser.ranges_m.size());
  const long index = std::lround(from_min / laser.angle_increment_rad) % bins;
  return laser.ranges_m[static_cast<std::size_t>(index)];
}

msgs::LaserScan one_scan(YdlidarG4Device& device, const yd::LaserScanOptions& options) {
  Host host;
  send(device, yd::Command::kStartScan, 0.0);
  run(device, host, 0.0, 0.5);
  EXPECT_FALSE(host.scans.empty());
  return host.scans.empty() ? msgs::LaserScan{}
                            : yd::to_laser_scan(host.scans.front(), options, 0.5);
}

TEST(YdlidarG4Device, TheScanIsCounterClockwiseInTheMountedFrame) {
  // A wall 1 m to the left (+y) and nothing to the right.
  RoundRoom wall(1.0);
  YdlidarG4Device device(wall, {});
  const msgs::LaserScan laser = one_scan(device, {});
  EXPECT_NEAR(range_at(laser, std::numbers::pi / 2.0), 1.0F, 0.05F);
  EXPECT_NEAR(range_at(laser, std::numbers::pi / 4.0), std::sqrt(2.0F), 0.05F);
  EXPECT_EQ(range_at(laser, -std::numbers::pi / 2.0), std::numeric_limits<float>::infinity());
}

TEST(YdlidarG4Device, TheMountingPoseAndTheBasePoseMoveTheRays) {
  RoundRoom room;
  YdlidarG4Device::Options options;
  options.mounting_pose = {0.5, 0.0, std::numbers::pi / 2.0};
  YdlidarG4Device device(room, options);
  yd::LaserScanOptions scan_options;
  scan_options.sensor_in_base = options.mounting_pose;
  // The lidar sits at (0.5, 0) looking to +y: ahead of it the wall is sqrt(4 - 0.25) m away, on its
  // right (+x in the room) 1.5 m, on its left (-x) 2.5 m.
  const msgs::LaserScan laser = one_scan(device, scan_options);
  EXPECT_EQ(laser.sensor_in_base, options.mounting_pose);
  EXPECT_NEAR(range_at(laser, 0.0), std::sqrt(3.75F), 0.05F);
  EXPECT_NEAR(range_at(laser, -std::numbers::pi / 2.0), 1.5F, 0.05F);
  EXPECT_NEAR(range_at(laser, std::numbers::pi / 2.0), 2.5F, 0.05F);

  // Turn the base a quarter to the left: the lidar is at (0, 0.5) looking to -x.
  room.set_base_pose({0.0, 0.0, std::numbers::pi / 2.0});
  YdlidarG4Device turned(room, options);
  const msgs::LaserScan turned_laser = one_scan(turned, scan_options);
  EXPECT_NEAR(range_at(turned_laser, -std::numbers::pi / 2.0), 1.5F, 0.05F);
  EXPECT_NEAR(range_at(turned_laser, std::numbers::pi / 2.0), 2.5F, 0.05F);
  EXPECT_NEAR(range_at(turned_laser, 0.0), std::sqrt(3.75F), 0.05F);
}

TEST(YdlidarG4Device, StopEndsTheStream) {
  RoundRoom room;
  YdlidarG4Device device(room, {});
  Host host;
  send(device, yd::Command::kStartScan, 0.0);
  run(device, host, 0.0, 1.0);
  // While it scans, the G4 ignores what is not a stop.
  send(device, yd::Command::kGetDeviceInfo, 1.0);
  send(device, yd::Command::kStopScan, 1.0);
  EXPECT_FALSE(device.scanning());
  run(device, host, 1.0, 1.1);
  const std::uint64_t packets = host.parser.stats().scan_packets;
  EXPECT_TRUE(device.transmit(5.0).empty());
  EXPECT_EQ(host.parser.stats().scan_packets, packets);
  EXPECT_EQ(host.responses.size(), 1U);  // the start-scan answer only
  EXPECT_EQ(host.parser.buffered_bytes(), 0U);

  // Idle again, it answers.
  send(device, yd::Command::kGetHealth, 5.0);
  host.take(device.transmit(5.1), 5.1);
  EXPECT_EQ(host.responses.size(), 2U);
}

TEST(YdlidarG4Device, BadChecksumSwitch) {
  RoundRoom room;
  YdlidarG4Device device(room, {});
  Host host;
  send(device, yd::Command::kStartScan, 0.0);
  run(device, host, 0.0, 0.5);
  const std::uint64_t good = host.parser.stats().scan_packets;
  EXPECT_GT(good, 100U);
  EXPECT_EQ(host.parser.stats().checksum_errors, 0U);

  device.set_bad_checksums(true);
  run(device, host, 0.5, 1.5);
  // A packet or two taken before the switch may still have been on the line.
  EXPECT_LE(host.parser.stats().scan_packets, good + 2);
  EXPECT_GT(host.parser.stats().checksum_errors, 200U);

  device.set_bad_checksums(false);
  const std::uint64_t errors = host.parser.stats().checksum_errors;
  run(device, host, 1.5, 2.5);
  EXPECT_LE(host.parser.stats().checksum_errors, errors + 2);
  EXPECT_GT(host.parser.stats().scan_packets, good + 200);
  EXPECT_GE(host.scans.size(), 3U);
}

TEST(YdlidarG4Device, FrequencyStepsChangeTheScanRate) {
  RoundRoom room;
  YdlidarG4Device device(room, {});
  Host host;
  send(device, yd::Command::kScanFrequencyUp1, 0.0);
  send(device, yd::Command::kScanFrequencyUp0p1, 0.0);
  send(device, yd::Command::kScanFrequencyDown0p1, 0.0);
  send(device, yd::Command::kScanFrequencyUp1, 0.0);
  host.take(device.transmit(0.1), 0.1);
  ASSERT_EQ(host.responses.size(), 4U);
  EXPECT_DOUBLE_EQ(*yd::decode_scan_frequency_hz(host.responses.back().payload), 9.0);
  EXPECT_DOUBLE_EQ(device.scan_rate_hz(), 9.0);
  send(device, yd::Command::kStartScan, 1.0);
  run(device, host, 1.0, 3.0);
  ASSERT_GE(host.scans.size(), 16U);
  EXPECT_NEAR(host.scans.back().samples.size(), 1000.0, 1.0);
  EXPECT_DOUBLE_EQ(*host.scans.back().scan_frequency_hz, 9.0);
}

TEST(YdlidarG4Device, IntensityFitsTheLineOnlyAtLowSamplingRates) {
  RoundRoom room;
  YdlidarG4Device::Options options;
  options.format = yd::SampleFormat::kIntensity8;
  EXPECT_THROW(YdlidarG4Device(room, options), std::invalid_argument);
  options.sampling_rate_hz = 4000;
  YdlidarG4Device device(room, options);
  Host host(yd::SampleFormat::kIntensity8);
  send(device, yd::Command::kStartScan, 0.0);
  run(device, host, 0.0, 1.0);
  ASSERT_GE(host.scans.size(), 5U);
  for (const yd::Sample& sample : host.scans.back().samples) {
    EXPECT_NEAR(sample.range_m, 2.0, 0.06);
    EXPECT_NEAR(sample.intensity, 85, 2);  // 255 / (1 + 2 m)
  }
  EXPECT_EQ(host.parser.stats().checksum_errors, 0U);
}

TEST(YdlidarG4Device, RefusesWhatTheG4CannotDo) {
  RoundRoom room;
  const auto with = [](auto change) {
    YdlidarG4Device::Options options;
    change(options);
    return options;
  };
  EXPECT_THROW(YdlidarG4Device(room, with([](auto& o) { o.scan_rate_hz = 20.0; })),
               std::invalid_argument);
  EXPECT_THROW(YdlidarG4Device(room, with([](auto& o) { o.sampling_rate_hz = 5000; })),
               std::invalid_argument);
  EXPECT_THROW(YdlidarG4Device(room, with([](auto& o) { o.samples_per_packet = 81; })),
               std::invalid_argument);
  // One sample a packet: the headers alone would overflow the line.
  EXPECT_THROW(YdlidarG4Device(room, with([](auto& o) { o.samples_per_packet = 1; })),
               std::invalid_argument);
  EXPECT_THROW(YdlidarG4Device(room, with([](auto& o) { o.max_range_m = 20.0; })),
               std::invalid_argument);
}

TEST(YdlidarG4Device, TheSeedMakesTheNoise) {
  RoundRoom room;
  const auto bytes_of = [&](std::uint64_t seed) {
    YdlidarG4Device::Options options;
    options.seed = seed;
    YdlidarG4Device device(room, options);
    send(device, yd::Command::kStartScan, 0.0);
    return device.transmit(0.3);
  };
  EXPECT_EQ(bytes_of(7), bytes_of(7));
  EXPECT_NE(bytes_of(7), bytes_of(8));
}

TEST(YdlidarG4Device, NothingWithinRangeIsDistanceZero) {
  // A room too large for the G4: every sample is a no-return.
  class Void final : public EmulatedWorld {
   public:
    geometry::Pose2D base_pose() const override { return {}; }
    void set_base_pose(const geometry::Pose2D&) override {}
    std::optional<double> cast_ray(geometry::Point2D, double, double, double) const override {
      return std::nullopt;
    }
  } nothing;
  YdlidarG4Device device(nothing, {});
  Host host;
  send(device, yd::Command::kStartScan, 0.0);
  run(device, host, 0.0, 0.5);
  ASSERT_FALSE(host.scans.empty());
  for (const yd::Sample& sample : host.scans.front().samples) EXPECT_EQ(sample.range_m, 0.0);
  const msgs::LaserScan laser = yd::to_laser_scan(host.scans.front(), {}, 0.0);
  for (const float range_m : laser.ranges_m) {
    EXPECT_EQ(range_m, std::numeric_limits<float>::infinity());
  }
}

}  // namespace
}  // namespace mobot::emulate
