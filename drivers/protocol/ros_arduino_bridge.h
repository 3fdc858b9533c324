#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mobot::protocol::arduino_bridge {

// The ROSArduinoBridge serial protocol as the Dashgo D1's base and IR boards speak it: a command
// is a letter and space-separated arguments ending in CR; the reply is one line ending in CR LF
// (the firmware's Serial.println). Replies are "OK", one integer, or integers separated by
// spaces; a command the firmware does not know gets "Invalid Command".

// The letters of the commands mobot sends.
inline constexpr char kGetBaud = 'b';
inline constexpr char kReadEncoders = 'e';     // -> "LEFT RIGHT" counts
inline constexpr char kResetEncoders = 'r';    // -> "OK"
inline constexpr char kMotorSpeeds = 'm';      // m LEFT RIGHT (ticks per PID frame) -> "OK"
inline constexpr char kUpdatePid = 'u';        // u Kp:Kd:Ki:Ko -> "OK"
inline constexpr char kReadSonars = 'p';       // -> four ranges in cm, 0 = no echo
inline constexpr char kReadBattery = 'v';      // -> battery voltage in tenths of a volt
inline constexpr char kReadEstopButton = 'j';  // -> 1 while the red button is pressed
inline constexpr char kAnalogRead = 'a';       // a PIN -> 10-bit ADC count

inline constexpr std::string_view kOk = "OK";
inline constexpr std::string_view kInvalidCommand = "Invalid Command";

// The firmware's wheel PID runs at a fixed 30 Hz: speeds are in encoder ticks per 1/30 s.
inline constexpr double kPidRateHz = 30.0;

struct PidGains {
  int kp = 20;
  int kd = 12;
  int ki = 0;
  int ko = 50;
};

// Commands, each with its terminating CR.
std::string command(char letter);
std::string motor_speeds_command(int left_ticks_per_frame, int right_ticks_per_frame);
std::string update_pid_command(const PidGains& gains);
std::string analog_read_command(int pin);

// A reply line (without its line end) as the integers it holds; nothing unless it is exactly
// `count` integers separated by single or repeated spaces, each within the firmware's long.
std::optional<std::vector<long>> parse_integers(std::string_view line, std::size_t count);
bool is_ok(std::string_view line);

// A wheel's angular speed as the firmware's set-point, rounded to the nearest tick per frame.
int ticks_per_frame(double wheel_radps, int ticks_per_wheel_rev);
// The reverse, for the emulated board.
double wheel_radps(double ticks_per_frame, int ticks_per_wheel_rev);

// The Dashgo firmware counts in 16 bits and wraps: consecutive readings become cumulative counts
// as long as a wheel turns less than half the counter (32768 ticks, 27 wheel turns) between two
// reads. The first reading starts the count at its own value.
class EncoderUnwrap {
 public:
  std::int64_t update(long raw_count);
  void reset() { started_ = false; }

 private:
  bool started_ = false;
  std::uint16_t last_raw_ = 0;
  std::int64_t total_ = 0;
};

}  // namespace mobot::protocol::arduino_bridge
