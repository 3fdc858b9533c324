#pragma once

#include <cstdint>
#include <deque>
#include <initializer_list>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "core/vision/pan_tilt_head.h"
#include "drivers/protocol/pololu_maestro.h"
#include "tools/emulate/emulated_device.h"
#include "tools/emulate/emulated_world.h"

namespace mobot::emulate {

struct MaestroDeviceOptions {
  // 6: a Micro Maestro; 12, 18 or 24: a Mini Maestro.
  int channels = 6;
  // The Maestro's "Enable CRC": each command must end with its CRC-7.
  bool crc = false;
  // The head: two servos and the ranger's analog input.
  int pan_channel = 0;
  int tilt_channel = 1;
  int range_channel = 2;
  protocol::maestro::ServoCalibration pan;
  protocol::maestro::ServoCalibration tilt;
  // Each servo channel's Min and Max (Channel Settings: a target beyond them is clamped). The
  // Maestro ships with 992-2000 us; a head's channels are opened up to its servos' travel.
  double min_pulse_us = 500.0;
  double max_pulse_us = 2500.0;
  // "On startup or error" of every servo channel, in quarter-microseconds; 0: off (the default).
  std::uint16_t home_qus = 0;
  // Where the ranger is: the head on the base (its lens position).
  vision::PanTiltHeadOptions head;
  // The LV-EZ: a reading every 49 ms of the nearest echo across its cone, in whole inches from 6
  // to 254 (254 also when nothing echoes), VCC/512 volts per inch.
  double range_cone_rad = 0.2617993877991494;  // 15 deg
  double range_period_s = 0.049;
  double ranger_supply_v = 5.0;
  // From a query's last byte to its answer's first; then each byte at the baud rate (a TTL line;
  // over USB the answers are as quick).
  double response_delay_s = 0.0005;
  unsigned baud = 115200;
};

// A Pololu Maestro with a pan/tilt head's two servos and a MaxBotix LV-EZ ranger on an analog
// input, from the line's side (compact protocol). Every 10 ms each servo's position moves toward
// its target within its speed limit ((0.25 us)/(10 ms)) and acceleration limit ((0.25 us)/(10 ms)/
// (80 ms)), braking to stop at the target, as the firmware does; a servo that is off jumps to its
// first target (the Maestro cannot know where it stands). Get Position answers a servo's pulse, or
// an input's 0..1023; the ranger reads the emulated world along the head's pan direction from the
// lens. A protocol or CRC error is recorded in the error register and sends every servo to its
// home (off by default), as the firmware does; Get Errors answers and clears the register. With
// bad checksums on (the line's `checksum` fault) the answers are garbled: the Maestro's carry no
// checksum, so the host sees noise. Mini SSC and the Pololu protocol are not emulated (a protocol
// error).
class MaestroDevice final : public EmulatedDevice {
 public:
  // Throws std::invalid_argument for a channel beyond `channels`, the ranger on a non-analog or
  // servo channel, a calibration or pulse range that is not positive, or a non-positive period.
  MaestroDevice(MaestroDeviceOptions options, const EmulatedWorld& world);

  std::string_view name() const override { return "maestro"; }
  const MaestroDeviceOptions& options() const { return options_; }
  void receive(std::span<const std::uint8_t> bytes, double now_s) override;
  std::vector<std::uint8_t> transmit(double now_s) override;
  void set_bad_checksums(bool on) override { garble_ = on; }

  // The true state, for tests and the emulator's commands.
  std::uint16_t position_qus(int channel) const;
  std::uint16_t target_qus(int channel) const;
  // A servo's joint angle through its calibration; nothing while it is off.
  std::optional<double> pan_rad() const;
  std::optional<double> tilt_rad() const;
  // What the ranger measures now (nothing: no echo) and the analog value it outputs.
  std::optional<double> ranger_range_m() const { return ranger_range_m_; }
  std::uint16_t ranger_value() const { return ranger_value_; }
  std::uint16_t errors() const { return errors_; }
  // As if the firmware had detected these errors (once): recorded, servos sent home.
  void raise_errors(std::uint16_t bits);
  // Raises these errors again every 10 ms until called with 0 (a serial time-out shorter than
  // the host's polls, a failing script).
  void keep_raising_errors(std::uint16_t bits) { repeating_errors_ = bits; }
  std::uint64_t commands() const { return commands_; }

 private:
  struct Channel {
    bool servo = true;
    std::uint16_t target = 0;  // 0: off
    double position = 0.0;     // quarter-microseconds; 0: off
    double velocity = 0.0;     // quarter-microseconds per 10 ms
    std::uint16_t speed = 0;
    std::uint16_t acceleration = 0;
  };
  struct TxByte {
    double release_s = 0.0;
    std::uint8_t byte = 0;
  };

  void advance(double now_s);
  void tick();
  void slew(Channel& channel) const;
  void sample_ranger();
  void apply(const protocol::maestro::ParsedCommand& command);
  void record_errors(std::uint16_t bits);
  void set_target(int channel, std::uint16_t target);
  void send(std::initializer_list<std::uint8_t> bytes);
  void send_u16(std::uint16_t value);
  std::uint16_t position_value(int channel) const;
  bool valid(int channel) const { return channel >= 0 && channel < options_.channels; }

  MaestroDeviceOptions options_;
  const EmulatedWorld& world_;
  vision::PanTiltHead head_;
  protocol::maestro::CommandParser parser_;
  std::vector<Channel> channels_;
  double now_s_ = 0.0;
  std::uint64_t ticks_ = 0;  // 10 ms periods since power-up
  double next_range_s_ = 0.0;
  std::optional<double> ranger_range_m_;
  std::uint16_t ranger_value_ = 0;
  std::uint16_t errors_ = 0;
  std::uint16_t repeating_errors_ = 0;
  std::deque<TxByte> tx_;
  double tx_busy_until_s_ = 0.0;
  bool garble_ = false;
  std::uint64_t commands_ = 0;
};

}  // namespace mobot::emulate
