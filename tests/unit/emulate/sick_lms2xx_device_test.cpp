#include "tools/emulate/devices/sick_lms2xx_device.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <vector>

#include "drivers/protocol/sick_lms2xx_commands.h"
#include "drivers/protocol/sick_lms2xx_scan.h"
#include "drivers/protocol/sick_lms2xx_telegram.h"

namespace mobot::emulate {
namespace {

namespace sick = protocol::sick;
using Bytes = std::vector<std::uint8_t>;
using Kind = sick::StreamEvent::Kind;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kWallX_m = 3.0;

// A wall across the whole map at x = 3 m, as tall as anything.
class WallWorld final : public EmulatedWorld {
 public:
  geometry::Pose2D base_pose() const override { return pose_; }
  void set_base_pose(const geometry::Pose2D& pose) override { pose_ = pose; }
  std::optional<double> cast_ray(geometry::Point2D from, double angle_rad, double /*height_m*/,
                                 double max_range_m) const override {
    const double c = std::cos(angle_rad);
    if (c <= 0.0) return std::nullopt;
    const double range_m = (kWallX_m - from.x) / c;
    if (range_m < 0.0 || range_m > max_range_m) return std::nullopt;
    return range_m;
  }

 private:
  geometry::Pose2D pose_;
};

// The host's end of the line: writes requests, reads what the device sent every millisecond.
struct Host {
  explicit Host(SickLms2xxDevice& lms) : device(lms) {}

  void send(const Bytes& bytes) { device.receive(bytes, now_s); }

  // Runs to `until_s`, returning what the host's parser found on the way.
  std::vector<sick::StreamEvent> run_until(double until_s) {
    std::vector<sick::StreamEvent> events;
    while (now_s < until_s - 1e-12) {
      now_s = std::min(until_s, now_s + 0.001);
      for (sick::StreamEvent& event : stream.feed(device.transmit(now_s))) {
        events.push_back(std::move(event));
      }
    }
    return events;
  }

  // Sends a request and returns the events of the next 0.3 s.
  std::vector<sick::StreamEvent> request(const Bytes& bytes) {
    send(bytes);
    return run_until(now_s + 0.3);
  }

  SickLms2xxDevice& device;
  sick::TelegramStream stream;
  double now_s = 0.0;
};

std::vector<sick::Telegram> telegrams(const std::vector<sick::StreamEvent>& events) {
  std::vector<sick::Telegram> out;
  for (const sick::StreamEvent& event : events) {
    if (event.kind == Kind::kTelegram) out.push_back(event.telegram);
  }
  return out;
}

std::vector<sick::MeasuredValues> scans(const std::vector<sick::StreamEvent>& events) {
  std::vector<sick::MeasuredValues> out;
  for (const sick::Telegram& telegram : telegrams(events)) {
    if (const auto values = sick::decode_measured_values(telegram)) out.push_back(*values);
  }
  return out;
}

// The start-up a driver does: 38400 baud, the variant, continuous output. Each step answers
// ACK and its reply; the host follows the baud rate once the reply is in.
void start(Host& host, const sick::Variant& variant, sick::BaudRate rate = sick::BaudRate::k38400,
           sick::OperatingMode mode = sick::OperatingMode::kContinuousAllValues) {
  std::vector<sick::StreamEvent> events = host.request(sick::baud_rate_request(rate));
  ASSERT_EQ(events.size(), 2U);
  ASSERT_EQ(events[0].kind, Kind::kAck);
  ASSERT_TRUE(sick::parse_mode_switch_reply(events[1].telegram)->accepted());
  ASSERT_EQ(host.device.requested_baud(), sick::bits_per_second(rate));

  events = host.request(sick::variant_request(variant));
  ASSERT_EQ(events.size(), 2U);
  ASSERT_EQ(events[0].kind, Kind::kAck);
  const std::optional<sick::VariantReply> reply = sick::parse_variant_reply(events[1].telegram);
  ASSERT_TRUE(reply.has_value());
  ASSERT_TRUE(reply->accepted);
  ASSERT_EQ(reply->variant(), variant);

  host.send(sick::mode_switch_request(mode));
  events = host.run_until(host.now_s + 0.02);
  ASSERT_GE(events.size(), 2U);
  ASSERT_EQ(events[0].kind, Kind::kAck);
  ASSERT_TRUE(sick::parse_mode_switch_reply(events[1].telegram)->accepted());
}

double wall_range_m(double sensor_x_m, double beam_rad) {
  return (kWallX_m - sensor_x_m) / std::cos(beam_rad);
}

TEST(SickLms2xxDevice, StartsAt9600AndFollowsTheStartUpSequence) {
  WallWorld world;
  SickLms2xxDevice lms(world);
  EXPECT_EQ(lms.name(), "sick_lms2xx");
  EXPECT_EQ(lms.requested_baud(), 9600);
  EXPECT_EQ(lms.operating_mode(), sick::OperatingMode::kOnRequest);
  Host host(lms);
  EXPECT_TRUE(host.run_until(1.0).empty()) << "on request: nothing unasked";

  // The reply to the baud switch goes out at 9600 (ACK + 9 bytes, 10.4 ms); only then 38400.
  host.send(sick::baud_rate_request(sick::BaudRate::k38400));
  std::vector<sick::StreamEvent> events = host.run_until(host.now_s + 0.005);
  EXPECT_EQ(lms.requested_baud(), 9600);
  for (sick::StreamEvent& event : host.run_until(host.now_s + 0.02)) {
    events.push_back(std::move(event));
  }
  EXPECT_EQ(lms.requested_baud(), 38400);
  ASSERT_EQ(events.size(), 2U);
  EXPECT_EQ(events[0].kind, Kind::kAck);
  EXPECT_EQ(sick::parse_mode_switch_reply(events[1].telegram),
            (sick::ModeSwitchReply{sick::kModeSwitchAccepted, 0x10}));

  start(host, {sick::ScanAngle::k180Deg, sick::AngularResolution::kOneDeg});
  EXPECT_EQ(lms.operating_mode(), sick::OperatingMode::kContinuousAllValues);
  EXPECT_FALSE(scans(host.run_until(host.now_s + 0.5)).empty());

  // Stop: the telegram on the line finishes, then ACK, A0, and silence.
  host.send(sick::mode_switch_request(sick::OperatingMode::kOnRequest));
  const std::vector<sick::StreamEvent> stop = host.run_until(host.now_s + 0.3);
  const std::vector<sick::Telegram> replies = telegrams(stop);
  ASSERT_FALSE(replies.empty());
  EXPECT_TRUE(sick::parse_mode_switch_reply(replies.back())->accepted());
  EXPECT_EQ(lms.operating_mode(), sick::OperatingMode::kOnRequest);
  EXPECT_TRUE(host.run_until(host.now_s + 1.0).empty());
}

TEST(SickLms2xxDevice, At38400BaudEveryEighthOneDegreeScanGoesOut) {
  WallWorld world;
  SickLms2xxDevice lms(world);
  Host host(lms);
  start(host, {sick::ScanAngle::k180Deg, sick::AngularResolution::kOneDeg});
  host.run_until(host.now_s + 0.5);
  const double from_s = host.now_s;
  const std::vector<sick::MeasuredValues> got = scans(host.run_until(from_s + 4.0));
  // 372 bytes take 96.9 ms at 38400 baud: the line is idle again at the 8th rotation, 9.375 Hz.
  EXPECT_NEAR(static_cast<double>(got.size()), 4.0 * 75.0 / 8.0, 1.0);
  EXPECT_EQ(host.stream.stats().crc_errors, 0U);
  EXPECT_GT(lms.scans_skipped(), 6 * lms.scans_sent());
  for (const sick::MeasuredValues& values : got) {
    ASSERT_EQ(values.values.size(), 181U);
    EXPECT_EQ(values.units, sick::MeasuringUnits::kCentimetres);
    EXPECT_FALSE(values.partial_scan);
  }
}

TEST(SickLms2xxDevice, At38400BaudHalfDegreeScansComeAtFourPointSevenHertz) {
  WallWorld world;
  SickLms2xxDevice lms(world);
  Host host(lms);
  start(host, {sick::ScanAngle::k180Deg, sick::AngularResolution::kHalfDeg});
  host.run_until(host.now_s + 0.5);
  const std::vector<sick::MeasuredValues> got = scans(host.run_until(host.now_s + 4.0));
  // 732 bytes, 190.6 ms; a scan is ready every 2nd rotation: every 16th rotation goes out.
  EXPECT_NEAR(static_cast<double>(got.size()), 4.0 * 75.0 / 16.0, 1.0);
  for (const sick::MeasuredValues& values : got) ASSERT_EQ(values.values.size(), 361U);
}

TEST(SickLms2xxDevice, At500kBaudEveryRotationGoesOut) {
  WallWorld world;
  SickLms2xxDevice lms(world);
  Host host(lms);
  start(host, {sick::ScanAngle::k180Deg, sick::AngularResolution::kOneDeg},
        sick::BaudRate::k500000);
  host.run_until(host.now_s + 0.5);
  const std::vector<sick::MeasuredValues> got = scans(host.run_until(host.now_s + 2.0));
  EXPECT_NEAR(static_cast<double>(got.size()), 2.0 * 75.0, 1.0);
}

TEST(SickLms2xxDevice, RangesSeeTheWallFromTheMount) {
  WallWorld world;
  SickLms2xxDevice::Options options;
  options.range_sigma_m = 0.0;
  SickLms2xxDevice lms(world, options);
  Host host(lms);
  start(host, {sick::ScanAngle::k180Deg, sick::AngularResolution::kHalfDeg});
  const std::vector<sick::MeasuredValues> got = scans(host.run_until(host.now_s + 0.5));
  ASSERT_FALSE(got.empty());
  const std::optional<msgs::LaserScan> scan = sick::to_laser_scan(got.back(), {});
  ASSERT_TRUE(scan.has_value());
  ASSERT_EQ(scan->ranges_m.size(), 361U);
  EXPECT_NEAR(scan->angle_min_rad, -90.0 * kDeg, 1e-6);
  EXPECT_NEAR(scan->angle_increment_rad, 0.5 * kDeg, 1e-7);
  for (std::size_t i = 0; i < scan->ranges_m.size(); ++i) {
    const double beam_rad =
        scan->angle_min_rad + static_cast<double>(i) * scan->angle_increment_rad;
    const double expected_m = std::abs(beam_rad) < 88.0 * kDeg ? wall_range_m(0.2, beam_rad) : 99.0;
    if (expected_m <= 80.0) {
      EXPECT_NEAR(scan->ranges_m[i], expected_m, 0.0051) << i;  // cm quantisation
    } else {
      EXPECT_GT(scan->ranges_m[i], scan->range_max_m) << "too far: no return at " << i;
    }
  }
}

TEST(SickLms2xxDevice, RangesFollowTheBasePoseAndCarryNoise) {
  WallWorld world;
  world.set_base_pose({1.0, 0.5, 30.0 * kDeg});
  SickLms2xxDevice::Options options;
  options.units = sick::MeasuringUnits::kMillimetres;
  SickLms2xxDevice lms(world, options);
  Host host(lms);
  start(host, {sick::ScanAngle::k180Deg, sick::AngularResolution::kOneDeg},
        sick::BaudRate::k500000);
  const std::vector<sick::MeasuredValues> got = scans(host.run_until(host.now_s + 0.5));
  ASSERT_GT(got.size(), 20U);
  // The mount is 0.2 m ahead of the base along its heading; beam i looks 30 deg to its left.
  const double mount_x_m = 1.0 + 0.2 * std::cos(30.0 * kDeg);
  double sum_sq = 0.0;
  int n = 0;
  for (const sick::MeasuredValues& values : got) {
    EXPECT_EQ(values.units, sick::MeasuringUnits::kMillimetres);
    const std::optional<msgs::LaserScan> scan = sick::to_laser_scan(values, {});
    ASSERT_TRUE(scan.has_value());
    for (int beam = -60; beam <= 40; beam += 10) {
      const double map_rad = (30.0 + beam) * kDeg;
      const double expected_m = wall_range_m(mount_x_m, map_rad);
      const double error_m = scan->ranges_m[static_cast<std::size_t>(beam + 90)] - expected_m;
      EXPECT_LT(std::abs(error_m), 0.06) << beam;
      sum_sq += error_m * error_m;
      ++n;
    }
    // 80 deg left of the base heading, +110 in the map: away from the wall, too far.
    EXPECT_GT(scan->ranges_m[170], scan->range_max_m);
  }
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.01, 0.002) << "sigma 0.01 m";
}

TEST(SickLms2xxDevice, SameSeedSameBytes) {
  WallWorld world;
  SickLms2xxDevice a(world);
  SickLms2xxDevice b(world);
  Host host_a(a);
  Host host_b(b);
  start(host_a, {sick::ScanAngle::k180Deg, sick::AngularResolution::kOneDeg});
  start(host_b, {sick::ScanAngle::k180Deg, sick::AngularResolution::kOneDeg});
  EXPECT_EQ(telegrams(host_a.run_until(1.5)), telegrams(host_b.run_until(1.5)));
}

TEST(SickLms2xxDevice, VariantSwitchRepliesWhatIsInForce) {
  WallWorld world;
  SickLms2xxDevice lms(world);
  Host host(lms);
  std::vector<sick::StreamEvent> events = host.request(
      sick::variant_request({sick::ScanAngle::k100Deg, sick::AngularResolution::kQuarterDeg}));
  ASSERT_EQ(telegrams(events).size(), 1U);
  // BB 01 64 00 19 00 10: accepted, 100 deg, 0.25 deg, status.
  EXPECT_EQ(telegrams(events)[0].payload, (Bytes{0xBB, 0x01, 0x64, 0x00, 0x19, 0x00, 0x10}));
  EXPECT_EQ(lms.variant(),
            (sick::Variant{sick::ScanAngle::k100Deg, sick::AngularResolution::kQuarterDeg}));

  // 180 deg at 0.25 deg is refused: BB 00 and the variant still in force.
  events = host.request(
      sick::variant_request({sick::ScanAngle::k180Deg, sick::AngularResolution::kQuarterDeg}));
  const std::optional<sick::VariantReply> refused = sick::parse_variant_reply(telegrams(events)[0]);
  ASSERT_TRUE(refused.has_value());
  EXPECT_FALSE(refused->accepted);
  EXPECT_EQ(refused->angle_deg, 100);
  EXPECT_EQ(refused->resolution_cdeg, 25);
}

TEST(SickLms2xxDevice, QuarterDegreeAtHundredDegreesIsOneTelegramPerFourRotations) {
  WallWorld world;
  SickLms2xxDevice lms(world);
  Host host(lms);
  start(host, {sick::ScanAngle::k100Deg, sick::AngularResolution::kQuarterDeg},
        sick::BaudRate::k500000);
  host.run_until(host.now_s + 0.2);
  const std::vector<sick::MeasuredValues> got = scans(host.run_until(host.now_s + 2.0));
  EXPECT_NEAR(static_cast<double>(got.size()), 2.0 * 75.0 / 4.0, 1.0);
  ASSERT_FALSE(got.empty());
  const std::optional<msgs::LaserScan> scan = sick::to_laser_scan(got.back(), {});
  ASSERT_TRUE(scan.has_value());
  EXPECT_EQ(scan->ranges_m.size(), 401U);
  EXPECT_NEAR(scan->angle_min_rad, -50.0 * kDeg, 1e-6);
  EXPECT_NEAR(scan->ranges_m[200], 2.8, 0.06);
}

TEST(SickLms2xxDevice, InterlacedPartsAt500kAssembleIntoQuarterDegreeScans) {
  WallWorld world;
  SickLms2xxDevice::Options options;
  options.range_sigma_m = 0.0;
  SickLms2xxDevice lms(world, options);
  Host host(lms);
  // Interlaced 0.25 deg over 180 deg: the 100 deg / 0.25 deg variant, then mode 0x2A.
  start(host, {sick::ScanAngle::k100Deg, sick::AngularResolution::kQuarterDeg},
        sick::BaudRate::k500000, sick::OperatingMode::kContinuousPartialScans);
  const std::vector<sick::MeasuredValues> parts = scans(host.run_until(host.now_s + 1.0));
  ASSERT_GT(parts.size(), 70U) << "a part every rotation";
  sick::InterlacedScanAssembler assembler(sick::AngularResolution::kQuarterDeg);
  std::vector<sick::MeasuredValues> complete;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    EXPECT_TRUE(parts[i].partial_scan);
    if (i > 0) {
      EXPECT_EQ(parts[i].partial_index, (parts[i - 1].partial_index + 1) % 4);
    }
    if (auto scan = assembler.add(parts[i])) complete.push_back(*scan);
  }
  EXPECT_NEAR(static_cast<double>(complete.size()), static_cast<double>(parts.size()) / 4.0, 1.0);
  ASSERT_FALSE(complete.empty());
  const std::optional<msgs::LaserScan> scan = sick::to_laser_scan(complete.back(), {});
  ASSERT_TRUE(scan.has_value());
  ASSERT_EQ(scan->ranges_m.size(), 721U);
  EXPECT_NEAR(scan->angle_increment_rad, 0.25 * kDeg, 1e-7);
  for (std::size_t i = 100; i < 620; i += 7) {
    const double beam_rad =
        scan->angle_min_rad + static_cast<double>(i) * scan->angle_increment_rad;
    EXPECT_NEAR(scan->ranges_m[i], wall_range_m(0.2, beam_rad), 0.0051) << i;
  }
}

TEST(SickLms2xxDevice, BadChecksumsSpoilEveryTelegramUntilSwitchedOff) {
  WallWorld world;
  SickLms2xxDevice lms(world);
  Host host(lms);
  start(host, {sick::ScanAngle::k180Deg, sick::AngularResolution::kOneDeg},
        sick::BaudRate::k500000);
  host.run_until(host.now_s + 0.2);
  lms.set_bad_checksums(true);
  host.run_until(host.now_s + 0.02);  // the telegram already on the line may still be good
  const std::uint64_t errors_before = host.stream.stats().crc_errors;
  std::vector<sick::StreamEvent> events = host.run_until(host.now_s + 0.5);
  EXPECT_TRUE(telegrams(events).empty());
  EXPECT_GT(host.stream.stats().crc_errors - errors_before, 30U);
  // A request's reply is spoiled too; its ACK has no CRC to spoil.
  events = host.request(sick::status_request());
  EXPECT_EQ(host.stream.stats().acks, 4U);

  lms.set_bad_checksums(false);
  host.run_until(host.now_s + 0.02);
  events = host.run_until(host.now_s + 0.5);
  EXPECT_GT(scans(events).size(), 30U);
}

TEST(SickLms2xxDevice, ABadHostTelegramGetsNakAndNothingElse) {
  WallWorld world;
  SickLms2xxDevice lms(world);
  Host host(lms);
  Bytes damaged = sick::status_request();
  damaged.back() ^= 0x01;
  std::vector<sick::StreamEvent> events = host.request(damaged);
  ASSERT_EQ(events.size(), 1U);
  EXPECT_EQ(events[0].kind, Kind::kNak);

  // The request again, intact and one byte at a time: ACK and the status reply.
  for (const std::uint8_t byte : sick::status_request()) host.send(Bytes{byte});
  events = host.run_until(host.now_s + 0.3);
  ASSERT_EQ(events.size(), 2U);
  EXPECT_EQ(events[0].kind, Kind::kAck);
  const std::optional<sick::StatusReply> status = sick::parse_status_reply(events[1].telegram);
  ASSERT_TRUE(status.has_value());
  EXPECT_EQ(status->operating_mode, 0x25);
  EXPECT_EQ(status->angle_deg, 180);
  EXPECT_EQ(status->resolution_cdeg, 50);
  EXPECT_EQ(status->baud_bps, 9600);
  EXPECT_EQ(status->units(), sick::MeasuringUnits::kCentimetres);
  EXPECT_EQ(sick::range_bits_for_measuring_mode(status->measuring_mode), 13);
}

TEST(SickLms2xxDevice, UnknownCommandsAndWrongPasswordsAreRefused) {
  WallWorld world;
  SickLms2xxDevice lms(world);
  Host host(lms);
  // Command 0x10 (reset) is not modelled: ACK and 0x92.
  const Bytes reset = sick::encode_telegram(sick::kLmsAddress, Bytes{0x10});
  std::vector<sick::StreamEvent> events = host.request(reset);
  ASSERT_EQ(events.size(), 2U);
  EXPECT_EQ(events[0].kind, Kind::kAck);
  EXPECT_EQ(events[1].telegram.command(), sick::kNotAcknowledgedReply);

  events = host.request(sick::installation_mode_request("WRONG_PW"));
  ASSERT_EQ(telegrams(events).size(), 1U);
  EXPECT_EQ(sick::parse_mode_switch_reply(telegrams(events)[0])->result,
            sick::kModeSwitchWrongPassword);
  EXPECT_EQ(lms.operating_mode(), sick::OperatingMode::kOnRequest);

  events = host.request(sick::installation_mode_request());
  EXPECT_TRUE(sick::parse_mode_switch_reply(telegrams(events)[0])->accepted());
  EXPECT_EQ(lms.operating_mode(), sick::OperatingMode::kInstallation);
}

TEST(SickLms2xxDevice, RejectsOptionsNoLmsHas) {
  WallWorld world;
  SickLms2xxDevice::Options options;
  options.initial_baud = 115200;
  EXPECT_THROW(SickLms2xxDevice(world, options), std::invalid_argument);
  options = {};
  options.measuring_mode = 0x3F;
  EXPECT_THROW(SickLms2xxDevice(world, options), std::invalid_argument);
  options = {};
  options.initial_variant = {sick::ScanAngle::k180Deg, sick::AngularResolution::kQuarterDeg};
  EXPECT_THROW(SickLms2xxDevice(world, options), std::invalid_argument);
  options = {};
  options.range_sigma_m = -1.0;
  EXPECT_THROW(SickLms2xxDevice(world, options), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::emulate
