#include "tools/emulate/devices/maestro_device.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/geometry/pose2d.h"
#include "core/numeric/finite.h"

namespace mobot::emulate {
namespace mx = protocol::maestro;

namespace {

constexpr double kTick_s = mx::kSpeedPeriod_s;
// The acceleration limit is per 80 ms: an eighth of it per 10 ms tick.
constexpr double kTicksPerAccelerationPeriod = mx::kAccelerationPeriod_s / mx::kSpeedPeriod_s;
// Past this, a gap between calls is jumped instead of run tick by tick.
constexpr double kMaxRunGap_s = 60.0;
constexpr double kLastTime_s = 1e9;
// The LV-EZ: whole inches, 6 in for anything nearer, 254 in at most (and without an echo).
constexpr double kMetresPerInch = 0.0254;
constexpr double kRangerMinInches = 6.0;
constexpr double kRangerMaxInches = 254.0;
constexpr double kRangerVoltsPerInchPerSupplyVolt = 1.0 / 512.0;
// Rays across the ranger's cone: its nearest echo.
constexpr int kRangerRays = 5;

void check_calibration(const char* axis, const mx::ServoCalibration& servo) {
  if (!finite_positive(servo.centre_us) || !finite_positive(servo.us_per_rad) ||
      (servo.sign != 1 && servo.sign != -1)) {
    throw std::invalid_argument(std::string("MaestroDevice: bad ") + axis + " calibration");
  }
}

}  // namespace

MaestroDevice::MaestroDevice(MaestroDeviceOptions options, const EmulatedWorld& world)
    : options_(options), world_(world), head_(options_.head), parser_(options_.crc) {
  const auto on_device = [&](int channel) { return channel >= 0 && channel < options_.channels; };
  if (options_.channels < 1 || options_.channels > mx::kChannels ||
      !on_device(options_.pan_channel) || !on_device(options_.tilt_channel) ||
      !on_device(options_.range_channel) || options_.pan_channel == options_.tilt_channel) {
    throw std::invalid_argument("MaestroDevice: a channel the device does not have or used twice");
  }
  if (options_.range_channel >= mx::kAnalogChannels ||
      options_.range_channel == options_.pan_channel ||
      options_.range_channel == options_.tilt_channel) {
    throw std::invalid_argument("MaestroDevice: the ranger needs an analog channel of its own");
  }
  check_calibration("pan", options_.pan);
  check_calibration("tilt", options_.tilt);
  if (!finite_positive(options_.min_pulse_us) || !(options_.max_pulse_us > options_.min_pulse_us) ||
      !finite_positive(options_.range_period_s) || !finite_positive(options_.ranger_supply_v) ||
      !(options_.range_cone_rad >= 0.0) || !(options_.response_delay_s >= 0.0) ||
      options_.baud == 0) {
    throw std::invalid_argument("MaestroDevice: bad pulse range, ranger or timing");
  }
  channels_.resize(static_cast<std::size_t>(options_.channels));
  channels_[static_cast<std::size_t>(options_.range_channel)].servo = false;
  sample_ranger();
  next_range_s_ = options_.range_period_s;
}

void MaestroDevice::receive(std::span<const std::uint8_t> bytes, double now_s) {
  advance(now_s);
  for (std::uint8_t byte : bytes) {
    const std::optional<mx::CommandEvent> event = parser_.feed(byte);
    if (!event) continue;
    if (event->errors != 0) record_errors(event->errors);
    if (event->command) {
      ++commands_;
      apply(*event->command);
    }
  }
}

std::vector<std::uint8_t> MaestroDevice::transmit(double now_s) {
  advance(now_s);
  std::vector<std::uint8_t> out;
  while (!tx_.empty() && tx_.front().release_s <= now_s_) {
    out.push_back(tx_.front().byte);
    tx_.pop_front();
  }
  return out;
}

std::uint16_t MaestroDevice::position_qus(int channel) const {
  if (!valid(channel)) return 0;
  return position_value(channel);
}

std::uint16_t MaestroDevice::target_qus(int channel) const {
  if (!valid(channel)) return 0;
  return channels_[static_cast<std::size_t>(channel)].target;
}

std::optional<double> MaestroDevice::pan_rad() const {
  return mx::angle_for_position(options_.pan, position_value(options_.pan_channel));
}

std::optional<double> MaestroDevice::tilt_rad() const {
  return mx::angle_for_position(options_.tilt, position_value(options_.tilt_channel));
}

void MaestroDevice::raise_errors(std::uint16_t bits) { record_errors(bits); }

void MaestroDevice::advance(double now_s) {
  // Time never runs backwards, and a time that is not a number does not move it.
  if (!std::isfinite(now_s) || now_s <= now_s_) return;
  now_s = std::min(now_s, kLastTime_s);
  const double behind_s = now_s - static_cast<double>(ticks_) * kTick_s;
  if (behind_s > kMaxRunGap_s) {
    // Long enough for every servo to have arrived.
    ticks_ += static_cast<std::uint64_t>((behind_s - kMaxRunGap_s) / kTick_s);
    for (Channel& channel : channels_) {
      if (channel.servo && channel.target != 0) channel.position = channel.target;
      channel.velocity = 0.0;
    }
  }
  // The epsilon keeps a tick that ends exactly at now_s from being lost to rounding.
  while (static_cast<double>(ticks_ + 1) * kTick_s <= now_s + 1e-9) {
    ++ticks_;
    tick();
  }
  if (now_s >= next_range_s_) {
    sample_ranger();
    next_range_s_ = std::max(next_range_s_ + options_.range_period_s, now_s);
  }
  now_s_ = now_s;
}

void MaestroDevice::tick() {
  if (repeating_errors_ != 0) record_errors(repeating_errors_);
  for (Channel& channel : channels_) {
    if (channel.servo) slew(channel);
  }
}

void MaestroDevice::slew(Channel& channel) const {
  if (channel.target == 0) {
    channel.position = 0.0;
    channel.velocity = 0.0;
    return;
  }
  const double target = channel.target;
  const double distance = target - channel.position;
  if (channel.position == 0.0 || distance == 0.0 ||
      (channel.speed == 0 && channel.acceleration == 0)) {
    channel.position = target;
    channel.velocity = 0.0;
    return;
  }
  const double direction = distance > 0.0 ? 1.0 : -1.0;
  const double speed_limit =
      channel.speed == 0 ? std::numeric_limits<double>::infinity() : channel.speed;
  double velocity = direction * std::min(speed_limit, std::abs(distance));
  if (channel.acceleration != 0) {
    // Ramp up within the acceleration, and down so as to stop at the target.
    const double step = channel.acceleration / kTicksPerAccelerationPeriod;
    const double braking = std::sqrt(2.0 * step * std::abs(distance));
    const double wanted = direction * std::min(speed_limit, std::max(braking, step));
    velocity = channel.velocity + std::clamp(wanted - channel.velocity, -step, step);
  }
  const double next = channel.position + velocity;
  if ((target - next) * direction <= 0.0) {
    channel.position = target;
    channel.velocity = 0.0;
  } else {
    channel.position = next;
    channel.velocity = velocity;
  }
}

void MaestroDevice::sample_ranger() {
  const vision::PanTilt joints{pan_rad().value_or(0.0), tilt_rad().value_or(0.0)};
  const vision::LensPosition lens = head_.lens_in_base(joints);
  const geometry::Pose2D base = world_.base_pose();
  const geometry::Point2D from = geometry::transform_point(base, {lens.x_m, lens.y_m});
  const double max_range_m = kRangerMaxInches * kMetresPerInch;
  std::optional<double> nearest;
  for (int i = 0; i < kRangerRays; ++i) {
    const double offset_rad =
        options_.range_cone_rad * (static_cast<double>(i) / (kRangerRays - 1) - 0.5);
    const std::optional<double> hit =
        world_.cast_ray(from, base.theta + joints.pan_rad + offset_rad, lens.z_m, max_range_m);
    if (hit && (!nearest || *hit < *nearest)) nearest = hit;
  }
  ranger_range_m_ = nearest;
  const double inches = nearest ? std::clamp(std::round(*nearest / kMetresPerInch),
                                             kRangerMinInches, kRangerMaxInches)
                                : kRangerMaxInches;
  const double volts = inches * options_.ranger_supply_v * kRangerVoltsPerInchPerSupplyVolt;
  ranger_value_ = static_cast<std::uint16_t>(
      std::clamp(std::round(volts / mx::kAnalogFullScaleV * mx::kAnalogFullScale), 0.0,
                 static_cast<double>(mx::kAnalogFullScale)));
}

void MaestroDevice::apply(const mx::ParsedCommand& command) {
  const int channel = command.channel;
  switch (command.command) {
    case mx::Command::kSetTarget:
      set_target(channel, command.value);
      return;
    case mx::Command::kSetSpeed:
    case mx::Command::kSetAcceleration: {
      if (!valid(channel)) return record_errors(mx::error_bit::kSerialProtocol);
      Channel& limited = channels_[static_cast<std::size_t>(channel)];
      if (command.command == mx::Command::kSetSpeed) {
        limited.speed = command.value;
      } else {
        limited.acceleration = std::min(command.value, mx::kMaxAcceleration);
      }
      return;
    }
    case mx::Command::kGetPosition:
      if (!valid(channel)) return record_errors(mx::error_bit::kSerialProtocol);
      return send_u16(position_value(channel));
    case mx::Command::kGetMovingState: {
      const bool moving = std::any_of(channels_.begin(), channels_.end(), [](const Channel& c) {
        return c.servo && c.target != 0 && c.position != c.target;
      });
      return send({static_cast<std::uint8_t>(moving ? 1 : 0)});
    }
    case mx::Command::kSetMultipleTargets:
      // The Micro Maestro does not have it.
      if (options_.channels <= 6) return record_errors(mx::error_bit::kSerialProtocol);
      for (std::size_t i = 0; i < command.targets.size(); ++i) {
        set_target(channel + static_cast<int>(i), command.targets[i]);
      }
      return;
    case mx::Command::kGetErrors:
      send_u16(errors_);
      errors_ = 0;
      return;
    case mx::Command::kGoHome:
      for (std::size_t i = 0; i < channels_.size(); ++i) {
        set_target(static_cast<int>(i), options_.home_qus);
      }
      return;
  }
}

void MaestroDevice::record_errors(std::uint16_t bits) {
  errors_ |= bits;
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    set_target(static_cast<int>(i), options_.home_qus);
  }
}

void MaestroDevice::set_target(int channel, std::uint16_t target) {
  if (!valid(channel)) return record_errors(mx::error_bit::kSerialProtocol);
  Channel& servo = channels_[static_cast<std::size_t>(channel)];
  if (!servo.servo) return;
  if (target == 0) {
    servo.target = 0;
    servo.position = 0.0;
    servo.velocity = 0.0;
    return;
  }
  const double min_qus = options_.min_pulse_us * mx::kQuarterUsPerUs;
  const double max_qus = options_.max_pulse_us * mx::kQuarterUsPerUs;
  servo.target = static_cast<std::uint16_t>(std::clamp<double>(target, min_qus, max_qus));
  // An unpowered servo's position is unknown: its first pulse is the target itself.
  if (servo.position == 0.0) servo.position = servo.target;
}

void MaestroDevice::send(std::initializer_list<std::uint8_t> bytes) {
  const double byte_s = 10.0 / static_cast<double>(options_.baud);
  double t_s = std::max(now_s_ + options_.response_delay_s, tx_busy_until_s_);
  for (std::uint8_t byte : bytes) {
    t_s += byte_s;
    // Garbled on the way out: the top bit flipped, so a 16-bit answer is off by 32768.
    tx_.push_back({t_s, static_cast<std::uint8_t>(garble_ ? byte ^ 0x80u : byte)});
  }
  tx_busy_until_s_ = t_s;
}

void MaestroDevice::send_u16(std::uint16_t value) {
  send({static_cast<std::uint8_t>(value & 0xFFu), static_cast<std::uint8_t>(value >> 8)});
}

std::uint16_t MaestroDevice::position_value(int channel) const {
  const Channel& state = channels_[static_cast<std::size_t>(channel)];
  if (!state.servo) return channel == options_.range_channel ? ranger_value_ : 0;
  return static_cast<std::uint16_t>(std::lround(state.position));
}

}  // namespace mobot::emulate
