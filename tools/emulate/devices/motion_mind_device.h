#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <random>
#include <span>
#include <string_view>
#include <vector>

#include "drivers/protocol/motion_mind.h"
#include "tools/emulate/emulated_device.h"
#include "tools/emulate/emulated_world.h"

namespace mobot::emulate {

// A board that drives the tilt axis of a nodding laser: positive counts pitch it up, and its
// NEG_LIM switch closes at the lower end of the travel.
struct MotionMindTiltOptions {
  double counts_per_degree = 0.0;
  double lower_limit_deg = -5.0;
  double start_pitch_deg = 0.0;
};

struct MotionMindBoardOptions {
  // The address the board answers to at power-up; the accessors below name a board by it.
  std::uint8_t address = protocol::motion_mind::kDefaultAddress;
  // Quadrature counts (x4) per turn of the output shaft: the shaft's angle and speed from counts.
  double counts_per_rev = protocol::motion_mind::kR1WheelCountsPerRev;
  // The motor's top speed under full drive, in counts per PID period (600 on R1: 19.8 rad/s).
  double max_counts_per_period = 600.0;
  // The shaft speed follows the PID's target with this first-order lag.
  double speed_time_constant_s = 0.05;
  // Standard deviation of each period's travel as a fraction of it: a stopped shaft stays put.
  double speed_noise_fraction = 0.005;
  std::int32_t initial_position_counts = 0;
  std::optional<MotionMindTiltOptions> tilt;
};

struct MotionMindBusOptions {
  std::vector<MotionMindBoardOptions> boards;
  std::uint64_t seed = 1;
  int baud = protocol::motion_mind::kDefaultBaud;
  // A pause this long after the last byte ends a command.
  double end_of_command_gap_s = protocol::motion_mind::kEndOfCommandGap_s;
  // From the end of a command to the first reply byte (the data sheet allows up to 10 ms, and
  // 50 ms for WRITE_STORE).
  double response_delay_s = 0.002;
  double write_store_delay_s = 0.030;
};

// One serial line with Motion Mind 3 boards in mode 4 (serial PID control) on it. The line ends
// a command by a pause (end_of_command_gap_s), so a second command written before the pause is
// one bad command to every board, as on the real line. Each board runs its 5 ms PID period on a
// common clock: MOVEAT_VELOCITY and the move-to commands set the target speed, the shaft follows
// it with a first-order lag plus noise from the bus's seeded generator, and POSITION counts the
// travel (32 bits, wrapping). The board addressed answers (ACK, or the registers it is asked
// for); the others, and all boards for the broadcast address, keep quiet. CHANGE_SPEED belongs to
// the open-loop mode and goes unanswered. Reply bytes leave at
// the baud rate, one after the other. A gap of more than a minute between calls is jumped at
// the speeds of the moment, without noise.
class MotionMindBus final : public EmulatedDevice {
 public:
  // Throws std::invalid_argument for a non-finite or non-positive scale, a negative time or
  // noise, or two boards with one address.
  explicit MotionMindBus(MotionMindBusOptions options);
  ~MotionMindBus() override;
  MotionMindBus(const MotionMindBus&) = delete;
  MotionMindBus& operator=(const MotionMindBus&) = delete;

  std::string_view name() const override { return "motion_mind"; }
  void receive(std::span<const std::uint8_t> bytes, double now_s) override;
  std::vector<std::uint8_t> transmit(double now_s) override;
  void set_bad_checksums(bool on) override { bad_checksums_ = on; }

  // The true state of the board configured with `address`, for the emulated world (nothing for
  // an unknown board). The angle is the shaft's turn since power-up.
  std::optional<double> shaft_angle_rad(std::uint8_t address) const;
  std::optional<double> shaft_speed_radps(std::uint8_t address) const;
  std::optional<std::int32_t> position_register(std::uint8_t address) const;
  // Only for a tilt board.
  std::optional<double> tilt_pitch_deg(std::uint8_t address) const;

  // Commands the boards took as such, and byte runs they dropped (bad length, command or
  // checksum).
  std::uint64_t commands() const { return commands_; }
  std::uint64_t rejected_commands() const { return rejected_commands_; }

 private:
  class Board;
  struct TxByte {
    double release_s = 0.0;
    std::uint8_t byte = 0;
  };

  void advance(double now_s);
  void run_boards_to(double t_s);
  void end_command(double t_s);
  void send(protocol::motion_mind::Packet reply, double start_s);
  const Board* find(std::uint8_t address) const;

  MotionMindBusOptions options_;
  std::vector<std::unique_ptr<Board>> boards_;
  std::mt19937_64 rng_;
  double now_s_ = 0.0;
  std::uint64_t periods_ = 0;  // PID periods run since power-up
  std::vector<std::uint8_t> rx_;
  bool rx_overflow_ = false;
  double last_rx_s_ = 0.0;
  std::deque<TxByte> tx_;
  double tx_busy_until_s_ = 0.0;
  bool bad_checksums_ = false;
  std::uint64_t commands_ = 0;
  std::uint64_t rejected_commands_ = 0;
};

struct MotionMindBaseGeometry {
  double track_m = 0.60;
  double wheel_radius_m = 0.075;
  // +1 when a board's positive counts roll its wheel forward, -1 for a mirrored motor.
  int left_sign = 1;
  int right_sign = 1;
};

// Moves the emulated world's base by what the left and right boards' shafts turned since the
// last update, as a differential drive (each step an arc of constant curvature). The bus and the
// world must outlive it.
class MotionMindBaseCoupling {
 public:
  // Throws std::invalid_argument for an unknown board or a non-positive track or radius.
  MotionMindBaseCoupling(const MotionMindBus& bus, std::uint8_t left_address,
                         std::uint8_t right_address, EmulatedWorld& world,
                         MotionMindBaseGeometry geometry = {});

  // Call after each MotionMindBus::transmit.
  void update();

 private:
  const MotionMindBus& bus_;
  std::uint8_t left_address_;
  std::uint8_t right_address_;
  EmulatedWorld& world_;
  MotionMindBaseGeometry geometry_;
  double last_left_rad_ = 0.0;
  double last_right_rad_ = 0.0;
};

}  // namespace mobot::emulate
