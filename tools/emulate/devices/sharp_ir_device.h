#pragma once

#include <random>
#include <string>
#include <vector>

#include "core/geometry/pose2d.h"
#include "drivers/protocol/line_framer.h"
#include "drivers/sim/sharp_ir_adc.h"
#include "tools/emulate/devices/timed_replies.h"
#include "tools/emulate/emulated_device.h"
#include "tools/emulate/emulated_world.h"

namespace mobot::emulate {

struct SharpIrDeviceOptions {
  std::vector<geometry::Pose2D> sensors_in_base;  // sensor i on analog pin i
  double height_m = 0.7;
  sim::SharpIrAdcOptions adc;
  unsigned baud = 115200;
  // analogRead and the sketch's averaging of a few samples.
  double reply_delay_s = 0.0005;
  std::uint64_t seed = 1;
};

// The Dashgo's Arduino Mega with its ring of Sharp IR rangers, from the line's side: `a PIN`
// answers the 10-bit count the sensor on that pin gives for the nearest surface along its beam
// (the simulator's model of the sensor: curve, per-unit gain, fold-back, noise, spikes).
class SharpIrDevice final : public EmulatedDevice {
 public:
  SharpIrDevice(SharpIrDeviceOptions options, const EmulatedWorld& world);

  std::string_view name() const override { return "ir"; }
  void receive(std::span<const std::uint8_t> bytes, double now_s) override;
  std::vector<std::uint8_t> transmit(double now_s) override;
  void set_bad_checksums(bool on) override { garble_replies_ = on; }

 private:
  std::string answer(const std::string& command);

  SharpIrDeviceOptions options_;
  const EmulatedWorld& world_;
  protocol::LineFramer framer_;
  std::mt19937_64 rng_;
  sim::SharpIrAdc adc_;
  bool garble_replies_ = false;
  TimedReplies replies_;
};

}  // namespace mobot::emulate
