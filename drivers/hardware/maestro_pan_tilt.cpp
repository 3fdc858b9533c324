#include "drivers/hardware/maestro_pan_tilt.h"

#include <array>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <spdlog/spdlog.h>

#include "drivers/serial/cycle_pacer.h"

namespace mobot::drivers::hardware {

namespace mx = protocol::maestro;

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
// A write of a cycle's commands is on the wire in well under this at any baud rate used.
constexpr std::chrono::milliseconds kWriteTimeout{100};

[[noreturn]] void refuse(const std::string& key, const std::string& why) {
  throw std::invalid_argument(key + ": " + why);
}

void check_channel(const std::string& key, int channel, int channels) {
  if (channel < 0 || channel >= channels) {
    refuse(key,
           std::to_string(channel) + " is not a channel of 0.." + std::to_string(channels - 1));
  }
}

void check_pulse(const std::string& key, const mx::ServoCalibration& servo, double angle_rad) {
  const double pulse_us = mx::pulse_us_for_angle(servo, angle_rad);
  if (!(pulse_us >= mx::kMinPulse_us && pulse_us <= mx::kMaxPulse_us)) {
    std::ostringstream why;
    why << angle_rad * kDegPerRad << " deg needs a " << pulse_us
        << " us pulse, beyond the Maestro's " << mx::kMinPulse_us << ".." << mx::kMaxPulse_us
        << " us";
    refuse(key, why.str());
  }
}

void check_servo(const std::string& axis, const MaestroServoOptions& servo, double min_rad,
                 double max_rad) {
  check_channel(axis + "_channel", servo.channel, mx::kChannels);
  const mx::ServoCalibration& calibration = servo.calibration;
  if (!(calibration.centre_us >= mx::kMinPulse_us && calibration.centre_us <= mx::kMaxPulse_us)) {
    refuse(axis + "_centre_us", "must lie within the Maestro's 64..4080 us");
  }
  if (!(calibration.us_per_rad > 0.0) || !std::isfinite(calibration.us_per_rad)) {
    refuse(axis + "_us_per_rad", "must be positive");
  }
  if (calibration.sign != 1 && calibration.sign != -1) refuse(axis + "_sign", "1 or -1");
  if (!(servo.max_accel_rad_s2 >= 0.0) || !std::isfinite(servo.max_accel_rad_s2)) {
    refuse(axis + "_accel_dps2", "must be 0 (unlimited) or positive");
  }
  check_pulse(axis + "_min_deg", calibration, min_rad);
  check_pulse(axis + "_max_deg", calibration, max_rad);
}

void validate(const MaestroPanTiltOptions& options) {
  const vision::PanTiltHeadOptions& head = options.head;
  check_servo("pan", options.pan, head.min_pan_rad, head.max_pan_rad);
  check_servo("tilt", options.tilt, head.min_tilt_rad, head.max_tilt_rad);
  if (options.tilt.channel == options.pan.channel) {
    refuse("tilt_channel", "channel " + std::to_string(options.pan.channel) + " is the pan's");
  }
  if (options.range_channel) {
    check_channel("range_channel", *options.range_channel, mx::kAnalogChannels);
    if (*options.range_channel == options.pan.channel ||
        *options.range_channel == options.tilt.channel) {
      refuse("range_channel",
             "channel " + std::to_string(*options.range_channel) + " drives a servo");
    }
    if (!(options.ranger.m_per_volt > 0.0) || !std::isfinite(options.ranger.m_per_volt)) {
      refuse("range_m_per_volt", "must be positive");
    }
    if (!(options.ranger.max_range_m > 0.0) || !std::isfinite(options.ranger.max_range_m)) {
      refuse("range_max_m", "must be positive");
    }
  }
  if (!(options.rate_hz > 0.0) || !std::isfinite(options.rate_hz)) {
    refuse("rate_hz", "must be positive");
  }
  if (options.reply_timeout.count() <= 0) refuse("reply_timeout_ms", "must be positive");
}

vision::PanTiltHead checked_head(const vision::PanTiltHeadOptions& head) {
  try {
    return vision::PanTiltHead(head);
  } catch (const std::invalid_argument& error) {
    refuse("head", error.what());
  }
}

}  // namespace

MaestroPanTilt::MaestroPanTilt(MaestroPanTiltOptions options)
    : options_(std::move(options)), head_(checked_head(options_.head)), health_(options_.name) {
  validate(options_);
  // Looking ahead, or as near as the limits allow.
  target_ = head_.clamp({});
  poll_queries_ = {mx::Query::kPosition, mx::Query::kPosition};
  if (options_.range_channel) poll_queries_.push_back(mx::Query::kPosition);
  poll_queries_.push_back(mx::Query::kErrors);
  thread_ = std::make_unique<serial::DeviceThread>(
      options_.serial, health_,
      [this](serial::SerialPort& port, const std::stop_token& stop) { session(port, stop); });
}

MaestroPanTilt::~MaestroPanTilt() { stop(); }

void MaestroPanTilt::start() { thread_->start(); }
void MaestroPanTilt::stop() { thread_->stop(); }

void MaestroPanTilt::set_target(const vision::PanTilt& joints) {
  const std::lock_guard lock(mutex_);
  vision::PanTilt next = target_;
  if (std::isfinite(joints.pan_rad)) next.pan_rad = joints.pan_rad;
  if (std::isfinite(joints.tilt_rad)) next.tilt_rad = joints.tilt_rad;
  target_ = head_.clamp(next);
}

vision::PanTilt MaestroPanTilt::target() const {
  const std::lock_guard lock(mutex_);
  return target_;
}

vision::PanTilt MaestroPanTilt::current() const {
  const std::lock_guard lock(mutex_);
  return {current_pan_rad_.value_or(target_.pan_rad), current_tilt_rad_.value_or(target_.tilt_rad)};
}

std::optional<msgs::HeadRange> MaestroPanTilt::take_range() {
  const std::lock_guard lock(mutex_);
  return std::exchange(range_, std::nullopt);
}

void MaestroPanTilt::session(serial::SerialPort& port, const std::stop_token& stop) {
  misses_ = 0;
  bad_replies_ = 0;
  error_polls_ = 0;
  // The error register first: the Maestro is there once it answers, and reading clears what
  // happened while no host listened (it does not count against this session).
  std::optional<std::vector<std::uint16_t>> errors;
  while (!stop.stop_requested() && !errors) {
    errors = exchange(port, command(mx::get_errors()), {mx::Query::kErrors});
  }
  if (!errors) return;
  if (errors->front() != 0) {
    spdlog::info("{}: the Maestro had recorded {}", health_.name(),
                 mx::error_names(errors->front()));
  }
  health_.set_ok();
  configure_servos(port);
  serial::CyclePacer pacer(options_.rate_hz);
  while (!stop.stop_requested()) {
    if (const auto values = exchange(port, cycle_commands(), poll_queries_)) {
      record(*values);
      health_.set_ok();
    }
    pacer.wait_next();
  }
}

void MaestroPanTilt::configure_servos(serial::SerialPort& port) {
  const vision::PanTiltHeadOptions& head = head_.options();
  mx::Packet commands;
  const auto add = [&](const MaestroServoOptions& servo, double rate_rad_s) {
    const auto channel = static_cast<std::uint8_t>(servo.channel);
    const mx::Packet speed =
        command(mx::set_speed(channel, mx::speed_for_rate(servo.calibration, rate_rad_s)));
    const mx::Packet acceleration = command(mx::set_acceleration(
        channel, mx::acceleration_for(servo.calibration, servo.max_accel_rad_s2)));
    commands.insert(commands.end(), speed.begin(), speed.end());
    commands.insert(commands.end(), acceleration.begin(), acceleration.end());
  };
  add(options_.pan, head.max_pan_rate_rad_s);
  add(options_.tilt, head.max_tilt_rate_rad_s);
  port.write_all(commands, kWriteTimeout);
}

mx::Packet MaestroPanTilt::command(mx::Packet packet) const {
  return options_.crc ? mx::with_crc(std::move(packet)) : packet;
}

mx::Packet MaestroPanTilt::cycle_commands() const {
  vision::PanTilt target;
  {
    const std::lock_guard lock(mutex_);
    target = target_;
  }
  std::vector<mx::Packet> packets{
      mx::set_target(static_cast<std::uint8_t>(options_.pan.channel),
                     mx::target_for_angle(options_.pan.calibration, target.pan_rad)),
      mx::set_target(static_cast<std::uint8_t>(options_.tilt.channel),
                     mx::target_for_angle(options_.tilt.calibration, target.tilt_rad)),
      mx::get_position(static_cast<std::uint8_t>(options_.pan.channel)),
      mx::get_position(static_cast<std::uint8_t>(options_.tilt.channel))};
  if (options_.range_channel) {
    packets.push_back(mx::get_position(static_cast<std::uint8_t>(*options_.range_channel)));
  }
  packets.push_back(mx::get_errors());
  mx::Packet commands;
  for (mx::Packet& packet : packets) {
    const mx::Packet framed = command(std::move(packet));
    commands.insert(commands.end(), framed.begin(), framed.end());
  }
  return commands;
}

std::optional<std::vector<std::uint16_t>> MaestroPanTilt::exchange(
    serial::SerialPort& port, const mx::Packet& commands, const std::vector<mx::Query>& queries) {
  // Answers that came after their time-out must not be taken for these.
  port.discard_input();
  collector_.expect(queries);
  port.write_all(commands, kWriteTimeout);
  const double line_s =
      serial::line_time_s(commands.size() + mx::reply_bytes(queries), port.options().baud);
  const auto deadline = std::chrono::steady_clock::now() + options_.reply_timeout +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(line_s));
  std::array<std::uint8_t, 64> buffer{};
  bool answered = false;
  while (collector_.state() == mx::ReplyCollector::State::kWaiting) {
    const auto left =
        std::chrono::ceil<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    const std::size_t count = port.read_some(buffer, left);
    health_.add_bytes(count);
    answered = answered || count > 0;
    collector_.feed(std::span(buffer.data(), count));
  }
  std::optional<std::vector<std::uint16_t>> values = collector_.values();
  collector_.cancel();
  if (values && !plausible(*values)) values.reset();
  if (values) {
    health_.add_frame();
  } else if (answered) {
    health_.add_checksum_error();
  }
  judge(answered, values.has_value());
  return values;
}

bool MaestroPanTilt::plausible(const std::vector<std::uint16_t>& values) const {
  // The answers' order: [pan, tilt, (range)], errors; or errors alone.
  if (!mx::plausible_errors(values.back())) return false;
  if (values.size() == 1) return true;
  if (!mx::plausible_servo_position(values[0]) || !mx::plausible_servo_position(values[1])) {
    return false;
  }
  return !options_.range_channel || mx::plausible_analog(values[2]);
}

void MaestroPanTilt::judge(bool answered, bool well_formed) {
  misses_ = answered ? 0 : misses_ + 1;
  bad_replies_ = !answered || well_formed ? 0 : bad_replies_ + 1;
  if (misses_ >= options_.misses_before_silent) throw serial::DeviceFault("silent");
  if (bad_replies_ >= options_.bad_replies_before_garbage) throw serial::DeviceFault("garbage");
}

void MaestroPanTilt::note_errors(std::uint16_t errors) {
  if (errors == 0) {
    error_polls_ = 0;
    return;
  }
  last_errors_.store(errors, std::memory_order_relaxed);
  if (error_polls_++ == 0) {
    spdlog::warn("{}: the Maestro reports {}", health_.name(), mx::error_names(errors));
  }
  // Errors that keep coming (a serial time-out shorter than the poll, a running script that
  // fails) keep sending the servos home between two cycles.
  if (error_polls_ >= options_.error_polls_before_refused) throw serial::DeviceFault("refused");
}

void MaestroPanTilt::record(const std::vector<std::uint16_t>& values) {
  const std::optional<double> pan = mx::angle_for_position(options_.pan.calibration, values[0]);
  const std::optional<double> tilt = mx::angle_for_position(options_.tilt.calibration, values[1]);
  std::optional<msgs::HeadRange> range;
  if (options_.range_channel) {
    range.emplace();
    range->range_m = mx::range_from_analog(values[2], options_.ranger);
    range->range_max_m = options_.ranger.max_range_m;
  }
  {
    const std::lock_guard lock(mutex_);
    // A servo that is off (after an error sent it home) keeps its last known angle.
    if (pan) current_pan_rad_ = pan;
    if (tilt) current_tilt_rad_ = tilt;
    if (range) range_ = range;
  }
  polls_.fetch_add(1, std::memory_order_relaxed);
  note_errors(values.back());
}

}  // namespace mobot::drivers::hardware
