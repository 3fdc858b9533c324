#include "tools/emulate/devices/dashgo_base_device.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "drivers/protocol/ros_arduino_bridge.h"

namespace mobot::emulate {
namespace {

namespace bridge = protocol::arduino_bridge;

// The firmware's counters are 16-bit: what `e` prints is the count wrapped to a signed short.
long wrapped16(double ticks) {
  const auto whole = static_cast<std::int64_t>(std::llround(ticks));
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(whole & 0xFFFF));
}

// The sketch splits a command's arguments at spaces (and the PID's at colons) and reads each
// with atoi: "m 10 -3" -> {10, -3}.
std::vector<long> arguments(const std::string& command) {
  std::string text = command.substr(1);
  std::replace(text.begin(), text.end(), ':', ' ');
  std::vector<long> values;
  std::istringstream in(text);
  std::string word;
  while (in >> word) values.push_back(std::strtol(word.c_str(), nullptr, 10));
  return values;
}

}  // namespace

DashgoBaseDevice::DashgoBaseDevice(DashgoBaseDeviceOptions options, EmulatedWorld& world)
    : options_(std::move(options)),
      world_(world),
      framer_({.max_line_bytes = 64, .cr_ends_line = true}),
      rng_(options_.seed) {}

void DashgoBaseDevice::receive(std::span<const std::uint8_t> bytes, double now_s) {
  advance(now_s);
  std::vector<std::string> commands;
  framer_.feed(bytes, commands);
  for (const std::string& command : commands) {
    std::string reply = answer(command) + "\r\n";
    if (garble_replies_) {
      // A byte mangled on the line: the reply no longer parses.
      reply[std::uniform_int_distribution<std::size_t>(0, reply.size() - 3)(rng_)] ^= 0x5A;
    }
    const double due_s =
        now_s + options_.reply_delay_s + reply.size() * 10.0 / static_cast<double>(options_.baud);
    replies_.push(due_s, std::move(reply));
  }
}

std::vector<std::uint8_t> DashgoBaseDevice::transmit(double now_s) {
  advance(now_s);
  return replies_.take_due(now_s);
}

std::string DashgoBaseDevice::answer(const std::string& command) {
  const std::vector<long> args = arguments(command);
  switch (command.front()) {
    case bridge::kGetBaud:
      return std::to_string(options_.baud);
    case bridge::kReadEncoders:
      return std::to_string(wrapped16(left_ticks_ - left_ticks_zero_)) + " " +
             std::to_string(wrapped16(right_ticks_ - right_ticks_zero_));
    case bridge::kResetEncoders:
      left_ticks_zero_ = left_ticks_;
      right_ticks_zero_ = right_ticks_;
      return std::string(bridge::kOk);
    case bridge::kMotorSpeeds:
      if (args.size() != 2) return std::string(bridge::kInvalidCommand);
      last_motor_command_s_ = now_s_;
      target_left_tpf_ = static_cast<double>(args[0]);
      target_right_tpf_ = static_cast<double>(args[1]);
      return std::string(bridge::kOk);
    case bridge::kUpdatePid:
      return args.size() == 4 ? std::string(bridge::kOk) : std::string(bridge::kInvalidCommand);
    case bridge::kReadSonars:
      return sonar_ranges();
    case bridge::kReadBattery:
      return std::to_string(std::lround(options_.battery_v * 10.0));
    case bridge::kReadEstopButton:
      return estop_button_ ? "1" : "0";
    default:
      return std::string(bridge::kInvalidCommand);
  }
}

std::string DashgoBaseDevice::sonar_ranges() const {
  std::string out;
  const geometry::Pose2D base = world_.base_pose();
  for (const geometry::Pose2D& mount : options_.sonars_in_base) {
    const geometry::Pose2D sonar = geometry::compose(base, mount);
    const std::optional<double> range_m = world_.cast_ray(
        {sonar.x, sonar.y}, sonar.theta, options_.sonar_height_m, options_.sonar_range_max_m);
    if (!out.empty()) out += ' ';
    out += std::to_string(range_m ? std::lround(*range_m * 100.0) : 0L);
  }
  return out;
}

void DashgoBaseDevice::advance(double now_s) {
  constexpr double kMaxStep_s = 0.005;
  const double metres_per_tick =
      2.0 * std::numbers::pi * options_.wheel_radius_m / options_.ticks_per_wheel_rev;
  std::normal_distribution<double> noise(0.0, options_.wheel_speed_noise_fraction);
  while (now_s_ < now_s) {
    const double dt_s = std::min(kMaxStep_s, now_s - now_s_);
    now_s_ += dt_s;
    if (now_s_ - last_motor_command_s_ > options_.auto_stop_s) {
      target_left_tpf_ = 0.0;
      target_right_tpf_ = 0.0;
    }
    const double blend = 1.0 - std::exp(-dt_s / options_.wheel_time_constant_s);
    left_tpf_ += (target_left_tpf_ - left_tpf_) * blend;
    right_tpf_ += (target_right_tpf_ - right_tpf_) * blend;
    const double left_step = left_tpf_ * (1.0 + noise(rng_)) * bridge::kPidRateHz * dt_s;
    const double right_step = right_tpf_ * (1.0 + noise(rng_)) * bridge::kPidRateHz * dt_s;
    left_ticks_ += left_step;
    right_ticks_ += right_step;

    const double forward_m = (left_step + right_step) / 2.0 * metres_per_tick;
    const double turn_rad = (right_step - left_step) * metres_per_tick / options_.track_m;
    geometry::Pose2D pose = world_.base_pose();
    const double heading = pose.theta + turn_rad / 2.0 + (forward_m < 0.0 ? std::numbers::pi : 0.0);
    const std::optional<double> clear_m = world_.cast_ray(
        {pose.x, pose.y}, heading, options_.sonar_height_m, options_.body_radius_m + 0.5);
    // Against a wall the wheels spin (the encoders count) and the base stays.
    if (!clear_m || *clear_m > options_.body_radius_m + std::abs(forward_m)) {
      pose.x += forward_m * std::cos(pose.theta + turn_rad / 2.0);
      pose.y += forward_m * std::sin(pose.theta + turn_rad / 2.0);
    }
    pose.theta = geometry::wrap_angle(pose.theta + turn_rad);
    world_.set_base_pose(pose);
  }
}

}  // namespace mobot::emulate
