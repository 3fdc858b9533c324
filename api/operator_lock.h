#pragma once

#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "api/ports/result.h"
#include "api/ports/token_admin_port.h"

namespace mobot::api {

// Who asks: the token's person, and the connection the request came on.
struct Claimant {
  Caller caller;
  std::uint64_t client_id = 0;  // the connection (an HTTP connection, or the stream it became)
  bool stream = false;          // the connection is a WebSocket stream
  std::string address;          // the peer, "ip:port"
};

struct OperatorHolder {
  Claimant claimant;
  double since_unix_s = 0.0;
};

// One operator drives at a time. The lock belongs to a person (a token): their dashboard's REST
// requests and stream are one operator, another token is another. A teleop or goal takes a free
// lock and refreshes its holder's dead-man; anybody else's is refused (kConflict operator_busy,
// naming the holder) until the holder releases it, an admin takes it over, the stream it was last
// used on closes, or no command came for the dead-man time. Stopping is never locked (e-stop,
// cancelling a goal, ending follow mode): anybody who sees danger stops the robot. Thread-safe; the clocks are passed in, so the rules are testable.
class OperatorLock {
 public:
  using Clock = std::chrono::steady_clock;

  // What a command changed in the lock, so that a command the robot refuses changes nothing.
  struct Change {
    OperatorHolder after;
    std::optional<OperatorHolder> before;
    Clock::time_point before_last_command{};
  };

  explicit OperatorLock(std::chrono::milliseconds dead_man = std::chrono::seconds(10));

  // Takes a free lock (or the own one). kConflict operator_busy when another person holds it.
  Result<OperatorHolder> acquire(const Claimant& who, Clock::time_point now, double now_unix_s);
  // Gives the own lock back; releasing a lock one does not hold is kConflict not_holder, and a
  // free lock stays free.
  Result<Done> release(const Claimant& who, Clock::time_point now);
  // An admin takes the lock whoever holds it.
  Result<OperatorHolder> take_over(const Claimant& who, Clock::time_point now, double now_unix_s);
  // A driving command (teleop, a goal): as acquire, and the holder's dead-man starts again. The
  // lock follows the connection the command came on, so that closing it lets the lock go.
  Result<OperatorHolder> command(const Claimant& who, Clock::time_point now, double now_unix_s);
  // command(), and what it changed.
  Result<Change> claim(const Claimant& who, Clock::time_point now, double now_unix_s);
  // Puts back what a claim changed, unless the lock has changed since (another command, a
  // release, a take-over): the robot refused the command it was for.
  void undo(const Change& change);
  // The connection closed: a lock last used on it (as a stream) lapses.
  void connection_closed(std::uint64_t client_id);
  std::optional<OperatorHolder> holder(Clock::time_point now) const;

 private:
  bool lapsed_locked(Clock::time_point now) const;
  DomainError busy_locked() const;

  const std::chrono::milliseconds dead_man_;
  mutable std::mutex mutex_;
  std::optional<OperatorHolder> holder_;
  Clock::time_point last_command_{};
};

}  // namespace mobot::api
