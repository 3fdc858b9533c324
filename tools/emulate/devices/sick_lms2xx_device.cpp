#include "tools/emulate/devices/sick_lms2xx_device.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <utility>

namespace mobot::emulate {
namespace {

namespace sick = protocol::sick;

constexpr double kRotation_hz = 75.0;
// Byte completions land on sums of byte times; this keeps a byte due at exactly now_s from
// waiting for the next call.
constexpr double kTimeEpsilon_s = 1e-9;
constexpr std::size_t kPasswordBytes = 8;
constexpr double kPartialFieldOfView_deg = 180.0;

bool streaming(sick::OperatingMode mode) {
  return mode == sick::OperatingMode::kContinuousAllValues ||
         mode == sick::OperatingMode::kContinuousPartialScans;
}

double rotation_end_s(std::int64_t rotation) {
  return static_cast<double>(rotation) / kRotation_hz;
}

}  // namespace

SickLms2xxDevice::SickLms2xxDevice(const EmulatedWorld& world)
    : SickLms2xxDevice(world, Options{}) {}

SickLms2xxDevice::SickLms2xxDevice(const EmulatedWorld& world, Options options)
    : world_(world), options_(std::move(options)), rng_(options_.seed) {
  const Options& o = options_;
  if (!geometry::is_finite(o.mount_in_base) || !std::isfinite(o.mount_height_m)) {
    throw std::invalid_argument("sick lms2xx: the mount pose and height must be finite");
  }
  if (!(o.range_sigma_m >= 0.0) || !(o.max_range_m > 0.0) || !(o.reply_delay_s >= 0.0) ||
      !std::isfinite(o.max_range_m) || !std::isfinite(o.range_sigma_m) ||
      !std::isfinite(o.reply_delay_s)) {
    throw std::invalid_argument(
        "sick lms2xx: noise and reply delay must be >= 0, the maximum range > 0, all finite");
  }
  if (!sick::baud_rate_from_bps(o.initial_baud)) {
    throw std::invalid_argument("sick lms2xx: the LMS talks 9600, 19200, 38400 or 500000 baud");
  }
  range_bits_ = sick::range_bits_for_measuring_mode(o.measuring_mode);
  if (range_bits_ == 0) {
    throw std::invalid_argument("sick lms2xx: the measuring mode must be one that sends ranges");
  }
  if (!sick::is_supported(o.initial_variant)) {
    throw std::invalid_argument("sick lms2xx: 180 deg at 0.25 deg is no LMS variant");
  }
  if (o.initial_mode != sick::OperatingMode::kOnRequest &&
      o.initial_mode != sick::OperatingMode::kContinuousAllValues &&
      o.initial_mode != sick::OperatingMode::kContinuousPartialScans) {
    throw std::invalid_argument("sick lms2xx: it powers up in mode 0x24, 0x25 or 0x2A");
  }
  active_ = Settings{o.initial_mode, o.initial_variant, o.initial_baud};
  scheduled_ = active_;
}

double SickLms2xxDevice::clamp_time(double now_s) {
  if (std::isfinite(now_s) && now_s > now_s_) now_s_ = now_s;
  return now_s_;
}

void SickLms2xxDevice::receive(std::span<const std::uint8_t> bytes, double now_s) {
  const double now = clamp_time(now_s);
  advance(now);
  for (const sick::StreamEvent& event : requests_.feed(bytes)) {
    if (event.kind == sick::StreamEvent::Kind::kBadCrc) {
      queue({sick::kNakByte}, now + options_.reply_delay_s, false);
    } else if (event.kind == sick::StreamEvent::Kind::kTelegram) {
      answer(event.telegram, now);
    }
  }
}

std::vector<std::uint8_t> SickLms2xxDevice::transmit(double now_s) {
  const double now = clamp_time(now_s);
  advance(now);
  std::vector<std::uint8_t> out;
  while (!line_.empty()) {
    Outgoing& o = line_.front();
    while (o.sent < o.bytes.size() &&
           o.start_s + static_cast<double>(o.sent + 1) * o.byte_time_s <= now + kTimeEpsilon_s) {
      if (o.sent == 0 && o.telegram && bad_checksums_ && o.bytes.size() >= 2) {
        o.bytes[o.bytes.size() - 1] ^= 0xFFU;
        o.bytes[o.bytes.size() - 2] ^= 0xFFU;
      }
      out.push_back(o.bytes[o.sent++]);
    }
    if (o.sent < o.bytes.size()) break;
    line_.pop_front();
  }
  return out;
}

void SickLms2xxDevice::advance(double now_s) {
  while (rotation_end_s(next_rotation_) <= now_s) {
    const double end_s = rotation_end_s(next_rotation_);
    apply_changes(end_s);
    if (streaming(active_.mode)) {
      rotation_done(end_s);
      ++next_rotation_;
      continue;
    }
    // The mirror turns but nothing goes out: skip to the next change, or to now.
    const double until_s = changes_.empty() ? now_s : std::min(now_s, changes_.front().at_s);
    const auto first_after = static_cast<std::int64_t>(std::ceil(until_s * kRotation_hz));
    next_rotation_ = std::max(next_rotation_ + 1, first_after);
  }
  apply_changes(now_s);
}

void SickLms2xxDevice::apply_changes(double until_s) {
  while (!changes_.empty() && changes_.front().at_s <= until_s) {
    const Settings& next = changes_.front().settings;
    if (next.mode != active_.mode || !(next.variant == active_.variant)) streaming_rotations_ = 0;
    active_ = next;
    changes_.pop_front();
  }
}

void SickLms2xxDevice::rotation_done(double at_s) {
  ++streaming_rotations_;
  const int rotations = sick::rotations_per_scan(active_.variant.resolution);
  const bool partial = active_.mode == sick::OperatingMode::kContinuousPartialScans;
  if (!partial && streaming_rotations_ % rotations != 0) return;
  if (line_free_s_ > at_s + kTimeEpsilon_s) {
    ++scans_skipped_;
    return;
  }
  sick::MeasuredValues values;
  if (partial) {
    const int step = 4 / rotations;
    const auto index = static_cast<int>((streaming_rotations_ - 1) % rotations) * step;
    const std::size_t count =
        static_cast<std::size_t>(kPartialFieldOfView_deg) + (index == 0 ? 1U : 0U);
    values = measure(-kPartialFieldOfView_deg / 2.0 + 0.25 * index, 1.0, count);
    values.partial_scan = true;
    values.partial_index = index;
  } else {
    const double angle_deg = static_cast<double>(active_.variant.angle);
    values = measure(-angle_deg / 2.0, sick::resolution_deg(active_.variant.resolution),
                     sick::values_per_scan(active_.variant));
  }
  ++scans_sent_;
  queue(sick::measured_values_telegram(values), at_s, true);
}

double SickLms2xxDevice::queue(std::vector<std::uint8_t> bytes, double earliest_s, bool telegram) {
  Outgoing o;
  o.start_s = std::max(earliest_s, line_free_s_);
  o.byte_time_s = sick::transmission_time_s(1, scheduled_.baud);
  o.telegram = telegram;
  o.bytes = std::move(bytes);
  line_free_s_ = o.start_s + static_cast<double>(o.bytes.size()) * o.byte_time_s;
  line_.push_back(std::move(o));
  return line_free_s_;
}

void SickLms2xxDevice::answer(const sick::Telegram& request, double now_s) {
  const double ack_s = now_s + options_.reply_delay_s;
  queue({sick::kAckByte}, ack_s, false);
  Settings next = scheduled_;
  std::vector<std::uint8_t> reply;
  switch (request.command()) {
    case sick::kModeSwitchCommand:
      reply = mode_switch(request.payload, next);
      break;
    case sick::kVariantCommand:
      reply = variant_switch(request.payload, next);
      break;
    case sick::kStatusCommand:
      reply =
          request.payload.size() == 1 ? status() : sick::not_acknowledged_reply(options_.status);
      break;
    default:
      reply = sick::not_acknowledged_reply(options_.status);
      break;
  }
  const double out_s = queue(std::move(reply), ack_s, true);
  if (!(next == scheduled_)) {
    scheduled_ = next;
    changes_.push_back(Change{out_s, next});
  }
}

std::vector<std::uint8_t> SickLms2xxDevice::mode_switch(const std::vector<std::uint8_t>& payload,
                                                        Settings& next) const {
  sick::ModeSwitchReply reply{sick::kModeSwitchAccepted, options_.status};
  if (payload.size() < 2) return sick::not_acknowledged_reply(options_.status);
  const std::uint8_t mode = payload[1];
  if (mode == static_cast<std::uint8_t>(sick::OperatingMode::kInstallation)) {
    if (payload.size() != 2 + kPasswordBytes) return sick::not_acknowledged_reply(options_.status);
    std::string password(kPasswordBytes, ' ');
    std::copy(payload.begin() + 2, payload.end(), password.begin());
    std::string expected(kPasswordBytes, ' ');
    std::copy_n(options_.password.begin(), std::min(options_.password.size(), kPasswordBytes),
                expected.begin());
    if (password == expected) {
      next.mode = sick::OperatingMode::kInstallation;
    } else {
      reply.result = sick::kModeSwitchWrongPassword;
    }
    return sick::mode_switch_reply(reply);
  }
  if (payload.size() != 2) return sick::not_acknowledged_reply(options_.status);
  for (const sick::OperatingMode known :
       {sick::OperatingMode::kContinuousAllValues, sick::OperatingMode::kOnRequest,
        sick::OperatingMode::kContinuousPartialScans}) {
    if (mode == static_cast<std::uint8_t>(known)) {
      next.mode = known;
      return sick::mode_switch_reply(reply);
    }
  }
  for (const sick::BaudRate rate : {sick::BaudRate::k9600, sick::BaudRate::k19200,
                                    sick::BaudRate::k38400, sick::BaudRate::k500000}) {
    if (mode == static_cast<std::uint8_t>(rate)) {
      next.baud = sick::bits_per_second(rate);
      return sick::mode_switch_reply(reply);
    }
  }
  return sick::not_acknowledged_reply(options_.status);
}

std::vector<std::uint8_t> SickLms2xxDevice::variant_switch(const std::vector<std::uint8_t>& payload,
                                                           Settings& next) const {
  if (payload.size() != 5) return sick::not_acknowledged_reply(options_.status);
  const auto angle_deg = static_cast<std::uint16_t>(payload[1] | (payload[2] << 8U));
  const auto resolution_cdeg = static_cast<std::uint16_t>(payload[3] | (payload[4] << 8U));
  const std::optional<sick::Variant> wanted = sick::variant_from(angle_deg, resolution_cdeg);
  sick::VariantReply reply;
  reply.status = options_.status;
  if (wanted && sick::is_supported(*wanted)) {
    next.variant = *wanted;
    reply.accepted = true;
  }
  reply.angle_deg = static_cast<std::uint16_t>(next.variant.angle);
  reply.resolution_cdeg = static_cast<std::uint16_t>(next.variant.resolution);
  return sick::variant_reply(reply);
}

std::vector<std::uint8_t> SickLms2xxDevice::status() const {
  sick::StatusReply reply;
  reply.software_version = options_.software_version;
  reply.operating_mode = static_cast<std::uint8_t>(scheduled_.mode);
  reply.measuring_mode = options_.measuring_mode;
  reply.angle_deg = static_cast<std::uint16_t>(scheduled_.variant.angle);
  reply.resolution_cdeg = static_cast<std::uint16_t>(scheduled_.variant.resolution);
  reply.baud_bps = scheduled_.baud;
  reply.units_code = static_cast<std::uint8_t>(options_.units);
  reply.status = options_.status;
  return sick::status_reply(reply);
}

sick::MeasuredValues SickLms2xxDevice::measure(double first_deg, double step_deg,
                                               std::size_t count) {
  sick::MeasuredValues values;
  values.units = options_.units;
  values.status = options_.status;
  values.values.reserve(count);
  const geometry::Pose2D mount = geometry::compose(world_.base_pose(), options_.mount_in_base);
  for (std::size_t i = 0; i < count; ++i) {
    const double angle_deg = first_deg + static_cast<double>(i) * step_deg;
    values.values.push_back(range_value(mount, angle_deg * std::numbers::pi / 180.0));
  }
  return values;
}

std::uint16_t SickLms2xxDevice::range_value(const geometry::Pose2D& mount, double angle_rad) {
  const double metres = sick::metres_per_unit(options_.units);
  const std::uint16_t largest = sick::max_range_code(range_bits_);
  const double max_range_m = std::min(options_.max_range_m, largest * metres);
  const std::optional<double> hit_m = world_.cast_ray({mount.x, mount.y}, mount.theta + angle_rad,
                                                      options_.mount_height_m, max_range_m);
  const std::uint16_t too_far = sick::range_error_code(sick::RangeError::kTooFar, range_bits_);
  if (!hit_m || !(*hit_m <= max_range_m)) return too_far;
  double range_m = *hit_m;
  if (options_.range_sigma_m > 0.0) {
    range_m += std::normal_distribution<double>(0.0, options_.range_sigma_m)(rng_);
  }
  const double code = std::round(std::max(0.0, range_m) / metres);
  if (code > largest) return too_far;
  return static_cast<std::uint16_t>(code);
}

}  // namespace mobot::emulate
