#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace mobot::protocol::maestro {

// The serial protocol of the Pololu Maestro USB servo controllers (Micro Maestro 6, Mini Maestro
// 12/18/24), compact form (Maestro Servo Controller User's Guide, sections 5.c-5.e).
//
// A command is a command byte (MSB set) followed by data bytes (MSB clear): a 14-bit value goes
// as its low 7 bits, then its high 7 bits. Only the queries answer, immediately and in the order
// they were sent, with plain bytes: no framing, no address, no checksum (the optional CRC-7 covers
// the host's commands only). A 16-bit answer is little-endian. Set Target, Set Speed and Set
// Acceleration answer nothing. The driver uses the compact protocol only (the Pololu protocol,
// 0xAA + device number, serves daisy chains; Mini SSC, 0xFF, is not used).

enum class Command : std::uint8_t {
  kSetTarget = 0x84,           // channel, target (14 bits): quarter-microseconds on a servo
  kSetSpeed = 0x87,            // channel, speed (14 bits): 0.25 us per 10 ms; 0 unlimited
  kSetAcceleration = 0x89,     // channel, acceleration (14 bits, 0..255 taken): 0 unlimited
  kGetPosition = 0x90,         // channel -> position, 2 bytes little-endian
  kGetMovingState = 0x93,      // -> 1 byte: 1 while a speed- or acceleration-limited servo moves
  kSetMultipleTargets = 0x9F,  // count, first channel, count targets (Mini Maestros only)
  kGetErrors = 0xA1,           // -> the error register, 2 bytes little-endian; clears it
  kGoHome = 0xA2,              // every channel to its "on startup or error" setting
};

// Channels 0-11 can be analog inputs (0..1023 for 0..VCC, nominally 5 V); 12-23 digital inputs
// (exactly 0 or 1023). The Micro Maestro has channels 0-5 only.
inline constexpr int kChannels = 24;
inline constexpr int kAnalogChannels = 12;
inline constexpr std::uint16_t kMax14Bit = 0x3FFF;
inline constexpr std::uint16_t kAnalogFullScale = 1023;
inline constexpr double kAnalogFullScaleV = 5.0;
inline constexpr int kQuarterUsPerUs = 4;
// The widest pulses the Maestros generate (Mini Maestros at low rates; each channel's Min and
// Max in the Control Center narrow them: 992-2000 us out of the box).
inline constexpr double kMinPulse_us = 64.0;
inline constexpr double kMaxPulse_us = 4080.0;
// Speed is in (0.25 us) / (10 ms) and acceleration in (0.25 us) / (10 ms) / (80 ms) at the
// default 20 ms servo period (always on the Micro Maestro); the firmware takes at most 255 for an
// acceleration.
inline constexpr double kSpeedPeriod_s = 0.010;
inline constexpr double kAccelerationPeriod_s = 0.080;
inline constexpr std::uint16_t kMaxAcceleration = 255;
// The CRC-7 polynomial 0x91, computed LSB first (section 5.d).
inline constexpr std::uint8_t kCrc7Polynomial = 0x91;

// The error register (section 4.b). An error sends every channel to its "on startup or error"
// setting (by default: off, no pulses); Get Errors clears the register.
namespace error_bit {
inline constexpr std::uint16_t kSerialSignal = 1u << 0;   // a stop bit where none was due
inline constexpr std::uint16_t kSerialOverrun = 1u << 1;  // the UART's buffer overflowed
inline constexpr std::uint16_t kSerialRxBufferFull = 1u << 2;
inline constexpr std::uint16_t kSerialCrc = 1u << 3;       // a command failed its CRC-7
inline constexpr std::uint16_t kSerialProtocol = 1u << 4;  // unknown or interrupted command
inline constexpr std::uint16_t kSerialTimeout = 1u << 5;   // no command within its time-out
inline constexpr std::uint16_t kScriptStack = 1u << 6;
inline constexpr std::uint16_t kScriptCallStack = 1u << 7;
inline constexpr std::uint16_t kScriptProgramCounter = 1u << 8;
inline constexpr std::uint16_t kDefined = (1u << 9) - 1;
}  // namespace error_bit

// "serial_protocol|serial_crc" for the set bits; "none" for 0.
std::string error_names(std::uint16_t errors);

using Packet = std::vector<std::uint8_t>;

// CRC-7 of the bytes (the byte a CRC-enabled Maestro expects after each command).
std::uint8_t crc7(std::span<const std::uint8_t> bytes);
// `command` with its CRC byte appended.
Packet with_crc(Packet command);

// Commands. Values beyond 14 bits are clamped to 0x3FFF; a channel is sent as its low 7 bits
// (whether the Maestro has it is the caller's business: the emulator records a protocol error).
Packet set_target(std::uint8_t channel, std::uint16_t target_qus);
Packet set_speed(std::uint8_t channel, std::uint16_t speed);
Packet set_acceleration(std::uint8_t channel, std::uint16_t acceleration);
Packet set_multiple_targets(std::uint8_t first_channel, std::span<const std::uint16_t> targets_qus);
Packet get_position(std::uint8_t channel);
Packet get_moving_state();
Packet get_errors();
Packet go_home();

// A command as the Maestro reads it.
struct ParsedCommand {
  Command command = Command::kGoHome;
  std::uint8_t channel = 0;  // set target, speed, acceleration, get position; first channel
  std::uint16_t value = 0;   // target, speed or acceleration
  std::vector<std::uint16_t> targets;  // set multiple targets
  bool operator==(const ParsedCommand&) const = default;
};

// What one byte from the host completed: a command, or an error the Maestro records.
struct CommandEvent {
  std::optional<ParsedCommand> command;
  std::uint16_t errors = 0;  // error_bit::kSerialProtocol or kSerialCrc
};

// The Maestro's side of the line: cuts commands out of the host's bytes. A command byte the
// protocol does not know, a data byte outside a command, or a command byte before the last
// command was whole is a protocol error (the interrupted command is dropped; a new command byte
// starts afresh). With CRC on, each command must be followed by its CRC byte: a wrong one is a
// CRC error and the command is dropped.
class CommandParser {
 public:
  explicit CommandParser(bool crc = false) : crc_(crc) {}

  std::optional<CommandEvent> feed(std::uint8_t byte);
  bool crc() const { return crc_; }
  // Bytes held for a command not yet whole.
  std::size_t pending_bytes() const { return partial_.size(); }

 private:
  std::optional<CommandEvent> complete();

  bool crc_ = false;
  Packet partial_;
};

// What the host asks, for the bytes each answer takes.
enum class Query : std::uint8_t { kPosition, kMovingState, kErrors };
std::size_t reply_bytes(Query query);
std::size_t reply_bytes(std::span<const Query> queries);

// The answers to `queries`, sent in one go, decoded from `bytes`: nothing unless the bytes are
// exactly as many as the answers take (the line has no framing: a byte more or less means the
// answers cannot be told apart).
std::optional<std::vector<std::uint16_t>> decode_replies(std::span<const Query> queries,
                                                         std::span<const std::uint8_t> bytes);

// Collects the answers to one batch of queries from the bytes the line brings in chunks. It is
// whole once the answers' bytes have come; a byte beyond them (or a byte while nothing is
// awaited) is an overrun: noise or answers to an earlier batch, so the batch is not to be trusted.
class ReplyCollector {
 public:
  enum class State { kIdle, kWaiting, kComplete, kOverrun };
  struct Counters {
    std::uint64_t bytes = 0;
    std::uint64_t batches = 0;  // completed
    std::uint64_t overruns = 0;
    std::uint64_t abandoned = 0;  // batches given up by cancel() or a new expect()
  };

  // Awaits the answers to `queries` (a batch not yet whole is abandoned).
  void expect(std::vector<Query> queries);
  void cancel();
  State feed(std::span<const std::uint8_t> bytes);
  State state() const { return state_; }
  // The decoded answers once complete.
  std::optional<std::vector<std::uint16_t>> values() const;
  std::size_t pending_bytes() const { return bytes_.size(); }
  const Counters& counters() const { return counters_; }

 private:
  std::vector<Query> queries_;
  std::size_t needed_ = 0;
  Packet bytes_;
  State state_ = State::kIdle;
  Counters counters_;
};

// Whether an answer can be what the Maestro sends: a servo's position is 0 (no pulses) or a
// pulse within the Maestros' range; an analog input is 0..1023; the error register has only its
// defined bits; the moving state is 0 or 1. Noise rarely passes all of them at once.
bool plausible_servo_position(std::uint16_t position_qus);
bool plausible_analog(std::uint16_t value);
bool plausible_errors(std::uint16_t errors);
bool plausible_moving_state(std::uint16_t state);

// One servo's calibration: its pulse at joint angle 0, how far the pulse moves per radian, and
// which way (sign -1: a larger pulse turns the joint the negative way).
struct ServoCalibration {
  double centre_us = 1500.0;
  // 1000 us per 90 degrees, the usual hobby servo (500..2500 us for +/-90 deg).
  double us_per_rad = 2000.0 / 3.14159265358979323846;
  int sign = 1;
};

double pulse_us_for_angle(const ServoCalibration& servo, double angle_rad);
// The target for `angle_rad`, rounded to a quarter-microsecond and clamped to 14 bits (and above
// 0, which would switch the servo off); a non-finite angle is the centre.
std::uint16_t target_for_angle(const ServoCalibration& servo, double angle_rad);
// The joint angle of a reported position; nothing for 0 (the servo is off: the Maestro does not
// know where it is).
std::optional<double> angle_for_position(const ServoCalibration& servo, std::uint16_t position_qus);
// Set Speed's value for at most `rate_rad_s`, rounded down but at least 1; 0 (unlimited) for a
// rate that is not positive and finite.
std::uint16_t speed_for_rate(const ServoCalibration& servo, double rate_rad_s);
double rate_for_speed(const ServoCalibration& servo, std::uint16_t speed);
// Set Acceleration's value for at most `accel_rad_s2`, 1..255; 0 (unlimited) for an acceleration
// that is not positive and finite.
std::uint16_t acceleration_for(const ServoCalibration& servo, double accel_rad_s2);

// An analog ranger on an input channel: metres per volt of its output (the MaxBotix LV-EZ gives
// VCC/512 per inch: at 5 V, 512 x 0.0254 / 5 = 2.60096 m/V), and the range from which on a
// reading means "nothing echoed" (the LV-EZ reports about 254 in, 6.45 m, then).
struct RangerScale {
  double m_per_volt = 512.0 * 0.0254 / 5.0;
  double max_range_m = 6.0;
};

double analog_volts(std::uint16_t value);
// The range of an analog reading; nothing at or beyond max_range_m (no echo) or for a value
// beyond 1023 (not an analog reading).
std::optional<double> range_from_analog(std::uint16_t value, const RangerScale& scale);

}  // namespace mobot::protocol::maestro
