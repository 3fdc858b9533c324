#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace mobot::protocol::motion_mind {

// The binary serial protocol of the Solutions Cubed Motion Mind 3 DC motor controller (hardware
// version 3; data sheet revision 6, March 2013), in mode 4 (serial PID control).
//
// A command is: command byte, address byte, data (LSB first), checksum. The checksum is the low
// byte of the sum of every byte before it. The board has no start byte and no length field: it
// takes the bytes it received as one command once the line has been quiet for 5 ms, checks the
// command's length and checksum, and answers within 10 ms (50 ms for WRITE_STORE). So a host
// must wait for the answer (or its time-out) before it writes the next command, even to another
// board: two commands written back to back are one bad command to every board on the line.
//
// An answer is either the single byte ACK (0x06, no checksum) or address, data (LSB first),
// checksum (the low byte of the sum of address and data). READ and READ_REGISTER answer with the
// registers asked for; WRITE and WRITE_STORE with ACK; the motion commands with ACK, or with
// POSITION, VELOCITY and/or TIME when FUNCTION's RETPOS/RETVEL/RETTIME bits are set. A command for
// another address, for the broadcast address, or with a bad checksum gets no answer.

enum class Command : std::uint8_t {
  kChangeSpeed = 20,     // open-loop PWM duty (mode 3 only), -1023..+1023, 2 bytes
  kMoveToAbsolute = 21,  // 4-byte position in counts
  kMoveToRelative = 22,  // 4-byte offset in counts
  kMoveAtVelocity = 23,  // 2-byte speed in counts per PID period (mode 4)
  kWrite = 24,           // register index, then the register's 1, 2 or 4 bytes
  kWriteStore = 25,      // as kWrite, and copies the register to EEPROM
  kRead = 26,            // 4-byte mask: bit i asks for register i
  kRestore = 27,         // factory defaults to registers and EEPROM (ADDRESS becomes 1)
  kReset = 28,           // software reset
  kReadRegister = 29,    // one register index
};

enum class Register : std::uint8_t {
  kPosition = 0,          // R/W 4, signed: quadrature counts (x4 decoding)
  kVelocityLimit = 1,     // R/W 2
  kVelocityFf = 2,        // R/W 1
  kFunction = 3,          // R/W 2: FUNCTION bits below
  kPTerm = 4,             // R/W 2
  kITerm = 5,             // R/W 2
  kDTerm = 6,             // R/W 2
  kAddress = 7,           // R/W 1
  kPidScalar = 8,         // R/W 1
  kTimer = 9,             // R/W 1: limit-switch debounce in 5 ms steps
  kRcMax = 10,            // R/W 2
  kRcMin = 11,            // R/W 2
  kRcBand = 12,           // R/W 2
  kRcCount = 13,          // R 2
  kVelocity = 14,         // R 2, signed: mean of the last 64 counts per 5 ms
  kTime = 15,             // R 4: 5 ms steps since power-up
  kStatus = 16,           // R 2: STATUS bits below
  kRevision = 17,         // R 1
  kMode = 18,             // R 1
  kAnalogCon = 19,        // R 2
  kAnalogFbck = 20,       // R 2
  kPwmOut = 21,           // R 2, signed: -1023..+1023
  kIndexPos = 22,         // R 4, signed
  kVnLimit = 23,          // R/W 4, signed
  kVpLimit = 24,          // R/W 4, signed
  kPwmLimit = 25,         // R/W 2
  kDeadband = 26,         // R/W 2
  kDesiredPosition = 27,  // R 4, signed
  kAmpsLimit = 28,        // R/W 2: ~20 mA steps
  kAmps = 29,             // R 2: ~20 mA steps
  kFunction2 = 30,        // R/W 2
  kThermistor = 31,       // R 2
};
inline constexpr std::size_t kRegisterCount = 32;

inline constexpr std::uint8_t kAck = 0x06;
// Every board acts on a command sent here and none answers.
inline constexpr std::uint8_t kBroadcastAddress = 99;
inline constexpr std::uint8_t kDefaultAddress = 1;
// The board's receive buffer; bytes beyond it are lost.
inline constexpr std::size_t kMaxCommandBytes = 50;

// Timing of the data sheet.
inline constexpr double kPidPeriod_s = 0.005;
inline constexpr double kEndOfCommandGap_s = 0.005;
inline constexpr double kMaxResponseDelay_s = 0.010;
inline constexpr double kMaxWriteStoreResponseDelay_s = 0.050;
// SW1 switch 5 off; 9600 with it on, 38400 or 115200 through FUNCTION2 stored in EEPROM.
inline constexpr int kDefaultBaud = 19200;

// FUNCTION register bits.
namespace function_bit {
inline constexpr std::uint16_t kPosPowerUp = 1u << 0;
inline constexpr std::uint16_t kRetPos = 1u << 1;
inline constexpr std::uint16_t kRetVel = 1u << 2;
inline constexpr std::uint16_t kRetTime = 1u << 3;
inline constexpr std::uint16_t kSatProt = 1u << 4;
inline constexpr std::uint16_t kSavePos = 1u << 5;
inline constexpr std::uint16_t kVelLimit = 1u << 6;
inline constexpr std::uint16_t kActiveStop = 1u << 7;
inline constexpr std::uint16_t kEnableDeadband = 1u << 11;
inline constexpr std::uint16_t kVirtualLimit = 1u << 13;
inline constexpr std::uint16_t kDisablePid = 1u << 14;
inline constexpr std::uint16_t kDisableBlink = 1u << 15;
}  // namespace function_bit

// FUNCTION2 register bits (read at power-up for the baud rates).
namespace function2_bit {
inline constexpr std::uint16_t kOverTempDisable = 1u << 8;
inline constexpr std::uint16_t kBaud38400 = 1u << 10;
inline constexpr std::uint16_t kNewVelocityMode = 1u << 11;
inline constexpr std::uint16_t kBaud115200 = 1u << 12;
}  // namespace function2_bit

// STATUS register bits. The limit inputs are active low and debounced over TIMER x 5 ms; while
// one is set the board will not drive the motor further that way.
namespace status_bit {
inline constexpr std::uint16_t kNegativeLimit = 1u << 0;  // NEG_LIM (J4 P16) at 0 V
inline constexpr std::uint16_t kPositiveLimit = 1u << 1;  // POS_LIM (J4 P17) at 0 V
inline constexpr std::uint16_t kBrake = 1u << 2;
inline constexpr std::uint16_t kIndex = 1u << 3;
inline constexpr std::uint16_t kBadRc = 1u << 4;
inline constexpr std::uint16_t kVirtualNegativeLimit = 1u << 5;
inline constexpr std::uint16_t kVirtualPositiveLimit = 1u << 6;
inline constexpr std::uint16_t kCurrentLimit = 1u << 7;
inline constexpr std::uint16_t kPwmLimit = 1u << 8;
inline constexpr std::uint16_t kInPosition = 1u << 9;
inline constexpr std::uint16_t kTemperatureFault = 1u << 10;
}  // namespace status_bit

struct RegisterInfo {
  std::string_view name;
  std::uint8_t size_bytes = 0;
  bool is_signed = false;
  bool writable = false;
  std::int64_t min_value = 0;
  std::int64_t max_value = 0;
  std::int64_t default_value = 0;  // factory default, for the writable ones
};

const RegisterInfo& register_info(Register reg);
// Nothing for an index past the last register.
std::optional<Register> register_from_index(std::uint8_t index);

// A READ command's mask: bit i asks for register i.
using RegisterMask = std::uint32_t;
constexpr RegisterMask mask_of(Register reg) {
  return RegisterMask{1} << static_cast<unsigned>(reg);
}
// Bytes of data a READ of `mask` answers with (registers in index order).
std::size_t read_data_bytes(RegisterMask mask);
// Bytes of data a motion command answers with under this FUNCTION value; 0 means ACK.
std::size_t motion_data_bytes(std::uint16_t function_register);

using Packet = std::vector<std::uint8_t>;

std::uint8_t checksum(std::span<const std::uint8_t> bytes);

// Commands. Values out of a field's range are clamped to it.
Packet change_speed(std::uint8_t address, int pwm_duty);
Packet move_to_absolute(std::uint8_t address, std::int32_t position_counts);
Packet move_to_relative(std::uint8_t address, std::int32_t offset_counts);
Packet move_at_velocity(std::uint8_t address, int counts_per_period);
// Clamped to the register's range; a read-only register is sent as asked (the board ignores it).
Packet write_register(std::uint8_t address, Register reg, std::int64_t value);
Packet write_store_register(std::uint8_t address, Register reg, std::int64_t value);
Packet read_registers(std::uint8_t address, RegisterMask mask);
Packet read_register(std::uint8_t address, Register reg);
Packet restore_defaults(std::uint8_t address);
Packet reset(std::uint8_t address);

// A command as a board reads it.
struct ParsedCommand {
  Command command = Command::kReset;
  std::uint8_t address = 0;
  Register reg = Register::kPosition;  // kWrite, kWriteStore, kReadRegister
  std::int64_t value = 0;              // the data, sign-extended where the field is signed
  RegisterMask mask = 0;               // kRead
};

// What a board makes of the bytes it took as one command: nothing unless the command byte is
// known, the length is that command's (WRITE's follows from its register) and the checksum holds.
std::optional<ParsedCommand> parse_command(std::span<const std::uint8_t> bytes);

// What the host waits for after a command.
struct ExpectedReply {
  bool ack = true;           // the single byte 0x06
  std::uint8_t address = 0;  // otherwise address, data_bytes of data, checksum
  std::size_t data_bytes = 0;
};
ExpectedReply ack_reply();
ExpectedReply read_reply(std::uint8_t address, RegisterMask mask);
ExpectedReply read_register_reply(std::uint8_t address, Register reg);
// The answer to a motion command (change speed, move-to, move-at) under this FUNCTION value.
ExpectedReply motion_reply(std::uint8_t address, std::uint16_t function_register);

struct Reply {
  bool ack = false;
  std::uint8_t address = 0;
  std::vector<std::uint8_t> data;  // without address and checksum
};

// Bytes of a whole reply on the wire.
std::size_t reply_bytes(const ExpectedReply& expected);
// A reply as a board sends it: `data` framed by the address and checksum.
Packet encode_data_reply(std::uint8_t address, std::span<const std::uint8_t> data);

// The value of `reg` in the data of a READ of `mask`; nothing when the mask leaves it out or the
// data is short. Signed registers are sign-extended.
std::optional<std::int64_t> register_value(RegisterMask mask, Register reg,
                                           std::span<const std::uint8_t> data);

// What a motion command's answer carries under RETPOS/RETVEL/RETTIME.
struct MotionFeedback {
  std::optional<std::int32_t> position_counts;
  std::optional<std::int16_t> velocity_counts_per_period;
  std::optional<std::uint32_t> time_periods;
};
std::optional<MotionFeedback> decode_motion_reply(std::uint16_t function_register,
                                                  std::span<const std::uint8_t> data);

// Cuts the replies out of the bytes the line brings. The host arms it with the reply it waits for
// before it writes the command; it then passes on that reply once, whole and with a good checksum.
// A data reply is found by its address byte: a candidate whose checksum fails is counted and the
// search starts again one byte after its start, so a reply that follows garbage is still found.
// Bytes that arrive while nothing is awaited, or that cannot start the awaited reply, are
// discarded and counted. ACK has no checksum: a stray 0x06 while an ACK is awaited passes.
class ReplyParser {
 public:
  struct Counters {
    std::uint64_t bytes = 0;
    std::uint64_t replies = 0;
    std::uint64_t checksum_errors = 0;
    std::uint64_t discarded_bytes = 0;
    std::uint64_t abandoned = 0;  // replies given up by cancel() or a new expect()
  };

  // Awaits `expected`; a reply still awaited is abandoned and its partial bytes discarded.
  void expect(const ExpectedReply& expected);
  // Gives up the awaited reply (the host timed out).
  void cancel();
  bool awaiting() const { return expected_.has_value(); }

  // The awaited reply once it is complete. Bytes after it in the same call are discarded: the
  // line carries one reply per command.
  std::optional<Reply> feed(std::span<const std::uint8_t> bytes);

  const Counters& counters() const { return counters_; }
  // Bytes held for a reply not yet complete.
  std::size_t pending_bytes() const { return partial_.size(); }

 private:
  std::optional<Reply> take(std::uint8_t byte);
  // After a failed candidate: drops its first byte and what follows up to the next address byte.
  void resync();

  std::optional<ExpectedReply> expected_;
  std::vector<std::uint8_t> partial_;
  Counters counters_;
};

// Decoded STATUS register.
struct Status {
  bool negative_limit = false;
  bool positive_limit = false;
  bool brake = false;
  bool index = false;
  bool virtual_negative_limit = false;
  bool virtual_positive_limit = false;
  bool current_limit = false;
  bool pwm_limit = false;
  bool in_position = false;
  bool temperature_fault = false;
};
Status decode_status(std::uint16_t status_register);
inline bool negative_limit(std::uint16_t status_register) {
  return (status_register & status_bit::kNegativeLimit) != 0;
}
inline bool positive_limit(std::uint16_t status_register) {
  return (status_register & status_bit::kPositiveLimit) != 0;
}

// Units. In mode 4 the board decodes quadrature x4 and runs its PID every 5 ms; MOVEAT_VELOCITY
// and VELOCITY are in counts per PID period. With C counts per turn of the output shaft:
//   counts_per_period = radps / (2 pi) * C * 0.005.
// R1's wheels: C = 500 slots x4 x 19:1 = 38000, so one unit is 0.0331 rad/s (2.5 mm/s of a
// 0.075 m wheel) and 1 rad/s is 30.24 units.
inline constexpr double kR1WheelCountsPerRev = 500.0 * 4.0 * 19.0;
double counts_per_period_per_radps(double counts_per_rev);
// Rounded to the nearest unit, clamped to the 16-bit field; a non-finite speed is 0.
int velocity_setpoint(double radps, double counts_per_rev);
double setpoint_radps(double counts_per_period, double counts_per_rev);

// Rounding a set-point to whole units loses up to half a unit (0.017 rad/s on R1). Carrying the
// remainder to the next command makes the set-points average the exact speed over a few ticks,
// which matters for slow turns.
class SetpointDither {
 public:
  int next(double radps, double counts_per_rev);
  void reset() { residual_ = 0.0; }

 private:
  double residual_ = 0.0;
};

// POSITION is 32 bits and wraps: consecutive readings become cumulative counts as long as the
// shaft moves less than 2^31 counts between two reads. The first reading starts the count at its
// own value.
class PositionUnwrap {
 public:
  std::int64_t update(std::int32_t raw_counts);
  void reset() { started_ = false; }

 private:
  bool started_ = false;
  std::int32_t last_raw_ = 0;
  std::int64_t total_ = 0;
};

// THERMISTOR and AMPS in SI units, by the data sheet's formulas.
double thermistor_celsius(int thermistor_register);
double amps_register_amperes(int amps_register);

// Time the bytes of one exchange take on the wire (8N1: 10 bits a byte).
double wire_time_s(std::size_t bytes, int baud);
// The longest an exchange can take by the data sheet: the command on the wire, the 5 ms gap that
// ends it, the board's response delay and the reply on the wire.
double max_round_trip_s(std::size_t command_bytes, std::size_t reply_bytes, int baud,
                        bool write_store = false);

// The set-up of one board for mode 4 written with WRITE (not stored: the EEPROM has a limited
// number of writes and the board keeps its stored defaults).
struct BoardSetup {
  std::uint16_t function = function_bit::kRetPos;
  int p_term = 6000;
  int i_term = 35;
  int d_term = 0;
  std::optional<int> pid_scalar;     // board's default 14
  std::optional<int> amps_limit;     // ~20 mA steps; board's default 512 (10.24 A)
  std::optional<int> pwm_limit;      // 1..1023
  std::optional<int> timer_periods;  // limit-switch debounce, 5 ms steps; default 10
};
// R1: the wheels keep the board's PID defaults (Kp 6000, Ki 35, Kd 0); the tilt axis has Kp 6000,
// Ki 35, Kd 2. Both answer motion commands with POSITION.
BoardSetup r1_wheel_setup();
BoardSetup r1_tilt_setup();

struct Exchange {
  Packet command;
  ExpectedReply reply;
};
// The writes of `setup`, each answered by ACK (the RET bits change only a motion command's
// answer, so the order does not matter).
std::vector<Exchange> setup_exchanges(std::uint8_t address, const BoardSetup& setup);

}  // namespace mobot::protocol::motion_mind
