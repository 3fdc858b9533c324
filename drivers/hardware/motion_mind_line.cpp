#include "drivers/hardware/motion_mind_line.h"

#include <stdexcept>

namespace mobot::drivers::hardware {

namespace mm = protocol::motion_mind;

namespace {

constexpr std::int64_t kSerialPidMode = 4;
constexpr mm::RegisterMask kPresenceMask =
    mm::mask_of(mm::Register::kMode) | mm::mask_of(mm::Register::kRevision);
constexpr mm::RegisterMask kSeekMask =
    mm::mask_of(mm::Register::kPosition) | mm::mask_of(mm::Register::kStatus);
// The cycle rate follows about the last ten cycles.
constexpr double kRateSmoothing = 0.1;

bool passed(std::int64_t counts, std::int64_t mark, double radps) {
  return radps > 0.0 ? counts >= mark : counts <= mark;
}

}  // namespace

MotionMindLine::MotionMindLine(MotionMindLineOptions options)
    : options_(std::move(options)), health_(options_.name) {
  thread_ = std::make_unique<serial::DeviceThread>(
      options_.serial, health_,
      [this](serial::SerialPort& port, const std::stop_token& stop) { session(port, stop); });
}

MotionMindLine::~MotionMindLine() { stop(); }

MotionMindLine::BoardId MotionMindLine::add_board(const MotionMindBoardConfig& board) {
  if (started_) throw std::logic_error("MotionMindLine: boards are added before start()");
  const std::string which = "Motion Mind board " + std::to_string(board.address);
  if (board.address == mm::kBroadcastAddress) {
    throw std::invalid_argument(which + ": 99 is the broadcast address, which no board answers");
  }
  for (const auto& other : boards_) {
    if (other->config.address == board.address) {
      throw std::invalid_argument(which + ": the address is taken on this line");
    }
  }
  if ((board.setup.function & mm::function_bit::kRetPos) == 0) {
    throw std::invalid_argument(which + ": FUNCTION must set RETPOS");
  }
  if (!(board.counts_per_rev > 0.0)) {
    throw std::invalid_argument(which + ": counts per revolution must be positive");
  }
  auto added = std::make_unique<Board>();
  added->config = board;
  boards_.push_back(std::move(added));
  return boards_.size() - 1;
}

void MotionMindLine::start() {
  started_ = true;
  thread_->start();
}

void MotionMindLine::stop() { thread_->stop(); }

std::uint64_t MotionMindLine::command(BoardId board, const MotionMindCommand& command) {
  Board& target = *boards_.at(board);
  const std::lock_guard lock(mutex_);
  target.command = command;
  return ++target.generation;
}

void MotionMindLine::set_velocity(BoardId board, double radps) {
  MotionMindCommand velocity;
  velocity.radps = radps;
  command(board, velocity);
}

std::optional<std::array<std::int64_t, 2>> MotionMindLine::take_counts(BoardId first,
                                                                       BoardId second) {
  Board& a = *boards_.at(first);
  Board& b = *boards_.at(second);
  const std::lock_guard lock(mutex_);
  if (!a.fresh || !b.fresh || !a.counts || !b.counts) return std::nullopt;
  a.fresh = false;
  b.fresh = false;
  return std::array<std::int64_t, 2>{*a.counts, *b.counts};
}

std::optional<std::int64_t> MotionMindLine::counts(BoardId board) const {
  const Board& target = *boards_.at(board);
  const std::lock_guard lock(mutex_);
  return target.counts;
}

MotionMindSeekResult MotionMindLine::seek_result(BoardId board) const {
  const Board& target = *boards_.at(board);
  const std::lock_guard lock(mutex_);
  return target.seek;
}

double MotionMindLine::cycle_rate_hz() const {
  const double period_s = cycle_period_s_.load(std::memory_order_relaxed);
  return period_s > 0.0 ? 1.0 / period_s : 0.0;
}

void MotionMindLine::session(serial::SerialPort& port, const std::stop_token& stop) {
  try {
    for (const auto& board : boards_) start_board(port, *board);
    health_.set_ok();
    while (!stop.stop_requested()) {
      const auto started = std::chrono::steady_clock::now();
      for (const auto& board : boards_) run_board(port, *board);
      note_cycle(started);
    }
  } catch (const serial::DeviceFault&) {
    // A board that stopped making sense does not stop the others: they would run on at their
    // last set-point through the back-off.
    stop_boards(port);
    throw;
  }
  stop_boards(port);
}

void MotionMindLine::start_board(serial::SerialPort& port, Board& board) {
  const std::uint8_t address = board.config.address;
  board.misses = 0;
  board.bad_checksums = 0;
  const mm::Reply presence = ask(port, board, mm::read_registers(address, kPresenceMask),
                                 mm::read_reply(address, kPresenceMask));
  if (mm::register_value(kPresenceMask, mm::Register::kMode, presence.data) != kSerialPidMode) {
    // Another mode ignores MOVEAT_VELOCITY or reads the set-point from RC or analog inputs.
    throw serial::DeviceFault("refused");
  }
  for (const mm::Exchange& write : mm::setup_exchanges(address, board.config.setup)) {
    ask(port, board, write.command, write.reply);
  }
  board.dither.reset();
  board.seek_start_counts.reset();
  const mm::Reply stopped = ask(port, board, mm::move_at_velocity(address, 0),
                                mm::motion_reply(address, board.config.setup.function));
  const auto feedback = mm::decode_motion_reply(board.config.setup.function, stopped.data);
  // The count restarts at the board's own POSITION, which outlives the host's sessions (not the
  // board's power): positions the drivers keep, such as the tilt's limit, stay valid.
  board.unwrap.reset();
  if (feedback && feedback->position_counts) record_position(board, *feedback->position_counts);
}

void MotionMindLine::run_board(serial::SerialPort& port, Board& board) {
  const std::uint8_t address = board.config.address;
  const std::uint16_t function = board.config.setup.function;
  MotionMindCommand command;
  std::uint64_t generation = 0;
  {
    const std::lock_guard lock(mutex_);
    command = board.command;
    generation = board.generation;
  }
  mm::Packet packet;
  if (command.kind == MotionMindCommand::Kind::kHoldPosition) {
    board.dither.reset();
    // The target in the board's own 32-bit POSITION, wrapping as it does.
    const auto raw_target =
        static_cast<std::int32_t>(static_cast<std::uint32_t>(board.last_raw) +
                                  static_cast<std::uint32_t>(static_cast<std::uint64_t>(
                                      command.position_counts - board.last_counts)));
    packet = mm::move_to_absolute(address, raw_target);
  } else {
    packet = mm::move_at_velocity(address,
                                  board.dither.next(command.radps, board.config.counts_per_rev));
  }
  std::optional<std::int64_t> counts;
  if (const auto reply = exchange(port, board, packet, mm::motion_reply(address, function), true)) {
    const auto feedback = mm::decode_motion_reply(function, reply->data);
    if (feedback && feedback->position_counts) {
      counts = record_position(board, *feedback->position_counts);
    }
  }

  if (command.kind == MotionMindCommand::Kind::kSeekNegativeLimit) {
    const auto reply = exchange(port, board, mm::read_registers(address, kSeekMask),
                                mm::read_reply(address, kSeekMask), true);
    if (!reply) return;
    const auto raw = mm::register_value(kSeekMask, mm::Register::kPosition, reply->data);
    const auto status = mm::register_value(kSeekMask, mm::Register::kStatus, reply->data);
    if (!raw || !status) return;
    const std::int64_t now_counts = record_position(board, static_cast<std::int32_t>(*raw));
    if (!board.seek_start_counts) board.seek_start_counts = now_counts;
    if (mm::negative_limit(static_cast<std::uint16_t>(*status))) {
      MotionMindCommand next;
      next.radps = command.then_radps;
      if (command.then_travel_counts) {
        next.stop_at_counts = now_counts + *command.then_travel_counts;
      }
      board.seek_start_counts.reset();
      const std::lock_guard lock(mutex_);
      if (board.generation != generation) return;
      board.seek = {generation, true, now_counts, std::chrono::steady_clock::now()};
      board.command = next;
      ++board.generation;
    } else if (command.max_seek_counts &&
               *board.seek_start_counts - now_counts > *command.max_seek_counts) {
      board.seek_start_counts.reset();
      const std::lock_guard lock(mutex_);
      if (board.generation != generation) return;
      board.seek = {generation, false, now_counts, std::chrono::steady_clock::now()};
      board.command = MotionMindCommand{};
      ++board.generation;
    }
    return;
  }
  board.seek_start_counts.reset();
  if (command.kind == MotionMindCommand::Kind::kVelocity && command.stop_at_counts && counts &&
      command.radps != 0.0 && passed(*counts, *command.stop_at_counts, command.radps)) {
    // Holding the mark rather than stopping past it: the axis coasts on for a cycle and its lag.
    MotionMindCommand hold;
    hold.kind = MotionMindCommand::Kind::kHoldPosition;
    hold.position_counts = *command.stop_at_counts;
    finish_command(board, generation, hold);
  }
}

std::optional<mm::Reply> MotionMindLine::exchange(serial::SerialPort& port, Board& board,
                                                  const mm::Packet& command,
                                                  const mm::ExpectedReply& expected, bool judged) {
  // A reply that came after its time-out must not be taken for this one.
  port.discard_input();
  parser_.expect(expected);
  const std::uint64_t checksum_errors_before = parser_.counters().checksum_errors;
  port.write_all(command, options_.reply_timeout);
  const auto deadline = std::chrono::steady_clock::now() + options_.reply_timeout;
  std::array<std::uint8_t, 64> buffer{};
  std::optional<mm::Reply> reply;
  while (!reply) {
    const auto left =
        std::chrono::ceil<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    const std::size_t count = port.read_some(buffer, left);
    health_.add_bytes(count);
    reply = parser_.feed(std::span(buffer.data(), count));
  }
  if (!reply) parser_.cancel();
  const std::uint64_t checksum_errors = parser_.counters().checksum_errors - checksum_errors_before;
  for (std::uint64_t i = 0; i < checksum_errors; ++i) health_.add_checksum_error();
  if (reply) health_.add_frame();
  if (judged) judge(board, reply.has_value(), checksum_errors > 0);
  return reply;
}

mm::Reply MotionMindLine::ask(serial::SerialPort& port, Board& board, const mm::Packet& command,
                              const mm::ExpectedReply& expected) {
  for (;;) {
    if (auto reply = exchange(port, board, command, expected, true)) return std::move(*reply);
  }
}

void MotionMindLine::judge(Board& board, bool answered, bool bad_checksum) {
  if (answered) {
    board.misses = 0;
    board.bad_checksums = 0;
    return;
  }
  // A reply with a bad checksum was an answer, just a spoilt one: each kind counts in a row.
  if (bad_checksum) {
    board.misses = 0;
    ++board.bad_checksums;
  } else {
    board.bad_checksums = 0;
    ++board.misses;
  }
  if (board.misses >= options_.misses_before_silent) throw serial::DeviceFault("silent");
  if (board.bad_checksums >= options_.checksum_errors_before_fault) {
    throw serial::DeviceFault("checksum");
  }
}

std::int64_t MotionMindLine::record_position(Board& board, std::int32_t raw_counts) {
  const std::int64_t counts = board.unwrap.update(raw_counts);
  board.last_raw = raw_counts;
  board.last_counts = counts;
  const std::lock_guard lock(mutex_);
  board.counts = counts;
  board.fresh = true;
  return counts;
}

void MotionMindLine::finish_command(Board& board, std::uint64_t generation,
                                    const MotionMindCommand& next) {
  const std::lock_guard lock(mutex_);
  if (board.generation != generation) return;
  board.command = next;
  ++board.generation;
}

void MotionMindLine::stop_boards(serial::SerialPort& port) {
  for (const auto& board : boards_) {
    board->dither.reset();
    try {
      exchange(port, *board, mm::move_at_velocity(board->config.address, 0),
               mm::motion_reply(board->config.address, board->config.setup.function), false);
    } catch (const serial::SerialError&) {
      // The line is gone: nothing more reaches any board.
      return;
    }
  }
}

void MotionMindLine::note_cycle(std::chrono::steady_clock::time_point started) {
  const double period_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const double smoothed = cycle_period_s_.load(std::memory_order_relaxed);
  cycle_period_s_.store(
      smoothed > 0.0 ? smoothed + kRateSmoothing * (period_s - smoothed) : period_s,
      std::memory_order_relaxed);
  cycles_.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace mobot::drivers::hardware
