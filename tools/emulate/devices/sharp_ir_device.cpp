#include "tools/emulate/devices/sharp_ir_device.h"

#include <algorithm>
#include <cstdlib>

#include "drivers/protocol/ros_arduino_bridge.h"

namespace mobot::emulate {

namespace bridge = protocol::arduino_bridge;

SharpIrDevice::SharpIrDevice(SharpIrDeviceOptions options, const EmulatedWorld& world)
    : options_(std::move(options)),
      world_(world),
      framer_({.max_line_bytes = 64, .cr_ends_line = true}),
      rng_(options_.seed),
      adc_(options_.adc, options_.sensors_in_base.size(), rng_) {}

void SharpIrDevice::receive(std::span<const std::uint8_t> bytes, double now_s) {
  std::vector<std::string> commands;
  framer_.feed(bytes, commands);
  for (const std::string& command : commands) {
    std::string reply = answer(command) + "\r\n";
    if (garble_replies_) reply[0] ^= 0x5A;
    const double due_s =
        now_s + options_.reply_delay_s + reply.size() * 10.0 / static_cast<double>(options_.baud);
    replies_.push(due_s, std::move(reply));
  }
}

std::vector<std::uint8_t> SharpIrDevice::transmit(double now_s) { return replies_.take_due(now_s); }

std::string SharpIrDevice::answer(const std::string& command) {
  if (command.front() == bridge::kGetBaud) return std::to_string(options_.baud);
  if (command.front() != bridge::kAnalogRead || command.size() < 3) {
    return std::string(bridge::kInvalidCommand);
  }
  const long pin = std::strtol(command.c_str() + 2, nullptr, 10);
  // An unconnected analog input floats near the middle of the range.
  if (pin < 0 || static_cast<std::size_t>(pin) >= options_.sensors_in_base.size()) return "512";
  const auto sensor = static_cast<std::size_t>(pin);
  const geometry::Pose2D pose =
      geometry::compose(world_.base_pose(), options_.sensors_in_base[sensor]);
  const std::optional<double> distance_m =
      world_.cast_ray({pose.x, pose.y}, pose.theta, options_.height_m, options_.adc.far_distance_m);
  return std::to_string(adc_.counts(sensor, distance_m, rng_));
}

}  // namespace mobot::emulate
