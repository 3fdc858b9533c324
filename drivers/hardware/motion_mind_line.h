#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <stop_token>
#include <string>
#include <vector>

#include "drivers/protocol/motion_mind.h"
#include "drivers/serial/device_health.h"
#include "drivers/serial/device_thread.h"
#include "drivers/serial/serial_port.h"

namespace mobot::drivers::hardware {

// One Motion Mind 3 board on a line.
struct MotionMindBoardConfig {
  std::uint8_t address = protocol::motion_mind::kDefaultAddress;
  // Quadrature counts (x4) per turn of the shaft the speeds are given for: 38000 for an R1 wheel,
  // 360 x counts per degree for the tilt axis (its "shaft" is the pitch).
  double counts_per_rev = protocol::motion_mind::kR1WheelCountsPerRev;
  // Written at every session's start; FUNCTION must set RETPOS (each set-point's answer is the
  // position the line keeps).
  protocol::motion_mind::BoardSetup setup = protocol::motion_mind::r1_wheel_setup();
};

struct MotionMindLineOptions {
  serial::SerialOptions serial{
      .device = {}, .baud = protocol::motion_mind::kDefaultBaud, .dtr = {}, .rts = {}};
  // The health's name on /robot and /metrics: "base" for R1's wheel line.
  std::string name = "base";
  // The data sheet's longest exchange at 19200 baud is ~20.7 ms (command, 5 ms gap, 10 ms
  // response delay, reply); a reply later than this is lost.
  std::chrono::milliseconds reply_timeout{25};
  // Consecutive unanswered exchanges of one board that make the line "silent", and consecutive
  // replies of one board with a bad checksum that make it "checksum" (one is noise).
  int misses_before_silent = 2;
  int checksum_errors_before_fault = 3;
};

// What the line keeps telling a board, once per cycle (the board has no command watchdog: the
// set-point holds until the next one).
struct MotionMindCommand {
  enum class Kind {
    kVelocity,           // run at `radps`
    kSeekNegativeLimit,  // run at `radps` (< 0) until NEG_LIM closes, then at `then_radps`
    kHoldPosition,       // hold `position_counts` (MOVETO_ABSOLUTE)
  };
  Kind kind = Kind::kVelocity;
  double radps = 0.0;
  // kVelocity: once the counts pass this in the direction of travel, the board holds it.
  std::optional<std::int64_t> stop_at_counts;
  // kSeekNegativeLimit: the speed once the switch closed, for at most `then_travel_counts` from
  // where it closed (then held there), and the most the seek may travel before it gives up (a
  // switch that never closes must not drive the axis into its mechanical stop).
  double then_radps = 0.0;
  std::optional<std::int64_t> then_travel_counts;
  std::optional<std::int64_t> max_seek_counts;
  std::int64_t position_counts = 0;  // kHoldPosition, in the line's cumulative counts
};

// How the last seek of a board ended.
struct MotionMindSeekResult {
  // The seek's command, as command() numbered it (0: no seek ended yet).
  std::uint64_t generation = 0;
  // The switch closed; false: the seek travelled max_seek_counts without it.
  bool found = false;
  std::int64_t position_counts = 0;          // where the switch closed
  std::chrono::steady_clock::time_point at;  // when the line read it closed
};

// Several Motion Mind 3 boards on one serial line (R1: the two wheels and the tilt axis), driven
// by one device thread. A command ends only by 5 ms of silence and the boards share the line, so
// the thread runs strictly one exchange at a time: write, then wait for the answer or its
// time-out, even before a command to another board.
//
// Each session first checks every board (MODE must be 4, serial PID), writes its set-up and stops
// it, taking its first POSITION; then it cycles as fast as the line allows: per board in turn the
// set-point (MOVEAT_VELOCITY, dithered to the exact speed; MOVETO_ABSOLUTE to hold a position),
// whose answer is POSITION, plus POSITION and STATUS while the board seeks its limit switch.
// At 19200 baud a set-point exchange takes ~12 ms on the emulator (2 ms response delay) and up
// to ~21 ms by the data sheet (10 ms), plus a USB adapter's latency: two boards cycle at 41 Hz on
// the emulator (24 Hz at worst on the boards), three at 27 Hz (16 Hz), one exchange more while
// the tilt seeks its switch. Not the control loop's 50 Hz: the loop takes the newest counts when
// there are new ones, and odometry integrates whatever interval they span. When the
// session ends, for a stop or a board that stopped making sense, every board is sent a zero
// set-point (not when the line itself is gone: nothing reaches them then).
class MotionMindLine {
 public:
  using BoardId = std::size_t;

  explicit MotionMindLine(MotionMindLineOptions options);
  ~MotionMindLine();
  MotionMindLine(const MotionMindLine&) = delete;
  MotionMindLine& operator=(const MotionMindLine&) = delete;

  // Before start(). Throws std::invalid_argument for the broadcast address, an address already on
  // the line or a set-up without RETPOS, std::logic_error once started.
  BoardId add_board(const MotionMindBoardConfig& board);

  void start();
  // Stops the thread (which stops the boards first).
  void stop();

  // Replaces the board's command from the next exchange on; returns the command's number.
  std::uint64_t command(BoardId board, const MotionMindCommand& command);
  void set_velocity(BoardId board, double radps);

  // The cumulative counts of both boards once each was read since the last call, or nothing.
  std::optional<std::array<std::int64_t, 2>> take_counts(BoardId first, BoardId second);
  // The newest cumulative counts of a board (nothing before its first answer).
  std::optional<std::int64_t> counts(BoardId board) const;
  MotionMindSeekResult seek_result(BoardId board) const;

  std::size_t board_count() const { return boards_.size(); }
  const MotionMindBoardConfig& board(BoardId board) const { return boards_.at(board)->config; }
  const serial::DeviceHealth& health() const { return health_; }
  const MotionMindLineOptions& options() const { return options_; }
  // Full cycles (every board once) run since start, and their recent rate.
  std::uint64_t cycles() const { return cycles_.load(std::memory_order_relaxed); }
  double cycle_rate_hz() const;

 private:
  struct Board {
    MotionMindBoardConfig config;
    // Shared with the control loop (mutex_).
    MotionMindCommand command;
    std::uint64_t generation = 0;  // numbers the commands
    std::optional<std::int64_t> counts;
    bool fresh = false;
    MotionMindSeekResult seek;
    // The device thread's own.
    protocol::motion_mind::SetpointDither dither;
    protocol::motion_mind::PositionUnwrap unwrap;
    std::int32_t last_raw = 0;
    std::int64_t last_counts = 0;
    std::optional<std::int64_t> seek_start_counts;
    int misses = 0;
    int bad_checksums = 0;
  };

  void session(serial::SerialPort& port, const std::stop_token& stop);
  void start_board(serial::SerialPort& port, Board& board);
  void run_board(serial::SerialPort& port, Board& board);
  // One exchange; judged exchanges count against the board and may throw DeviceFault.
  std::optional<protocol::motion_mind::Reply> exchange(
      serial::SerialPort& port, Board& board, const protocol::motion_mind::Packet& command,
      const protocol::motion_mind::ExpectedReply& expected, bool judged);
  // Repeats the exchange until it is answered (or the board is judged silent).
  protocol::motion_mind::Reply ask(serial::SerialPort& port, Board& board,
                                   const protocol::motion_mind::Packet& command,
                                   const protocol::motion_mind::ExpectedReply& expected);
  void judge(Board& board, bool answered, bool bad_checksum);
  std::int64_t record_position(Board& board, std::int32_t raw_counts);
  // Replaces the command the line itself finished, unless the control loop changed it meanwhile.
  void finish_command(Board& board, std::uint64_t generation, const MotionMindCommand& next);
  void stop_boards(serial::SerialPort& port);
  void note_cycle(std::chrono::steady_clock::time_point started);

  MotionMindLineOptions options_;
  serial::DeviceHealth health_;
  std::vector<std::unique_ptr<Board>> boards_;
  mutable std::mutex mutex_;
  protocol::motion_mind::ReplyParser parser_;
  std::atomic<std::uint64_t> cycles_{0};
  std::atomic<double> cycle_period_s_{0.0};  // smoothed
  bool started_ = false;
  std::unique_ptr<serial::DeviceThread> thread_;
};

}  // namespace mobot::drivers::hardware
