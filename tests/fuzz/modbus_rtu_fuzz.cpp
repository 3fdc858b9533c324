// Feeds arbitrary bytes, in chunks of varying size, to the Modbus RTU request framer and to the
// sensor bus model that answers through it. The master's side parses with libmodbus's own code;
// this is the slave's side, the part written here. Besides crashes it checks that every framed
// request has a valid CRC, that no byte is lost or made up, and that every reply is a well-formed
// frame with a valid CRC.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <span>
#include <vector>

#include "tools/emulate/devices/modbus_sensor_bus_device.h"

namespace {

using mobot::emulate::modbus_crc16;

// Walls 2 m around the origin, whatever the pose.
class RingWorld : public mobot::emulate::EmulatedWorld {
 public:
  mobot::geometry::Pose2D base_pose() const override { return pose_; }
  void set_base_pose(const mobot::geometry::Pose2D& pose) override { pose_ = pose; }
  std::optional<double> cast_ray(mobot::geometry::Point2D /*from*/, double /*angle_rad*/,
                                 double /*height_m*/, double max_range_m) const override {
    return 2.0 <= max_range_m ? std::optional<double>(2.0) : std::nullopt;
  }

 private:
  mobot::geometry::Pose2D pose_;
};

void require(bool condition) {
  if (!condition) std::abort();
}

bool crc_ok(std::span<const std::uint8_t> frame) {
  if (frame.size() < 4) return false;
  const std::uint16_t crc = modbus_crc16(frame.first(frame.size() - 2));
  return frame[frame.size() - 2] == (crc & 0xFF) && frame[frame.size() - 1] == (crc >> 8);
}

// Replies are exceptions (5 bytes) or reads (slave, function, count, data, CRC).
void check_replies(std::span<const std::uint8_t> bytes, bool spoiled) {
  std::size_t at = 0;
  while (at < bytes.size()) {
    require(bytes.size() - at >= 5);
    const std::uint8_t function = bytes[at + 1];
    std::size_t length = 5;
    if ((function & 0x80) == 0) {
      require(function >= 0x02 && function <= 0x04);
      length = 5 + std::size_t{bytes[at + 2]};
    }
    require(bytes.size() - at >= length);
    require(crc_ok(bytes.subspan(at, length)) != spoiled);
    at += length;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::uint8_t flags = data[0];
  const std::uint8_t pacing = data[1];
  const std::span<const std::uint8_t> input(data + 2, size - 2);

  RingWorld world;
  world.set_base_pose({0.0, 0.0, (flags & 0x70) * 0.01});
  mobot::emulate::ModbusSensorBusOptions options;
  options.baud = (flags & 0x08) != 0 ? 9600 : 115200;
  mobot::emulate::ModbusSensorBusDevice device(world, options, pacing);
  const bool spoiled = (flags & 0x01) != 0;
  device.set_bad_checksums(spoiled);
  device.set_limit_switch((flags & 0x02) != 0);
  if ((flags & 0x04) != 0) device.set_node_present(1 + pacing % 10, false);

  mobot::emulate::ModbusRtuRequestFramer framer;
  std::uint64_t framed_bytes = 0;
  std::vector<std::uint8_t> replies;
  double now_s = 0.0;
  std::size_t at = 0;
  std::size_t step = 0;
  while (at < input.size()) {
    // Chunk sizes from 1 to 16 and gaps from nothing to a few byte times, cycling with the
    // input's own bytes so the fuzzer steers both.
    const std::uint8_t steer = input[(at + step) % input.size()] ^ pacing;
    const std::size_t chunk = std::min<std::size_t>(1 + steer % 16, input.size() - at);
    const std::span<const std::uint8_t> bytes = input.subspan(at, chunk);
    for (const std::vector<std::uint8_t>& frame : framer.push(bytes)) {
      require(frame.size() >= 4 && frame.size() <= 268);
      require(crc_ok(frame));
      framed_bytes += frame.size();
    }
    device.receive(bytes, now_s);
    const std::vector<std::uint8_t> sent = device.transmit(now_s);
    replies.insert(replies.end(), sent.begin(), sent.end());
    at += chunk;
    ++step;
    now_s += (steer >> 4) * 1e-4;
  }
  require(framed_bytes + framer.discarded_bytes() + framer.buffered_bytes() == input.size());
  require(framer.buffered_bytes() <= 268);
  require(device.replies() <= device.requests());

  const std::vector<std::uint8_t> rest = device.transmit(now_s + 10.0);
  replies.insert(replies.end(), rest.begin(), rest.end());
  check_replies(replies, spoiled);
  return 0;
}
