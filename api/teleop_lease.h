#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>

#include "core/msgs/twist.h"

namespace mobot::api {

// A client's teleop as the audit trail sees it: the many commands of one drive are one start
// and one stop. A moving command starts a drive unless the last one's lease is still running; a
// standing command ends a running drive. A drive whose lease lapsed without a new command has
// already ended on the robot (the control loop records that lapse), so the next moving command
// starts a new one.
class TeleopLease {
 public:
  using Clock = std::chrono::steady_clock;
  enum class Change { kNone, kStarted, kStopped };

  Change note(const msgs::Twist& command, int ttl_ms, Clock::time_point now);
  // Whether a drive's lease runs at `now`, and until when.
  bool running(Clock::time_point now) const { return driving_ && now < until_; }
  // The last command moved the robot: its lease runs, or lapsed with no command after it.
  bool driving() const { return driving_; }
  Clock::time_point until() const { return until_; }
  // When the command that started or extended the running lease arrived.
  Clock::time_point last_command() const { return last_command_; }

 private:
  bool driving_ = false;
  Clock::time_point until_{};
  Clock::time_point last_command_{};
};

// The drives of REST clients, one per token: a REST client may send each command on a connection
// of its own, and one person driving is one drive. Thread-safe.
class TeleopLeases {
 public:
  TeleopLease::Change note(std::int64_t token_id, const msgs::Twist& command, int ttl_ms,
                           TeleopLease::Clock::time_point now);

 private:
  std::mutex mutex_;
  std::map<std::int64_t, TeleopLease> leases_;
};

}  // namespace mobot::api
