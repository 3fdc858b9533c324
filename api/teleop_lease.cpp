#include "api/teleop_lease.h"

namespace mobot::api {

TeleopLease::Change TeleopLease::note(const msgs::Twist& command, int ttl_ms,
                                      Clock::time_point now) {
  const bool moving = command.linear_mps != 0.0 || command.angular_radps != 0.0;
  const bool was_running = running(now);
  driving_ = moving;
  last_command_ = now;
  until_ = now + std::chrono::milliseconds(ttl_ms);
  if (moving) return was_running ? Change::kNone : Change::kStarted;
  return was_running ? Change::kStopped : Change::kNone;
}

TeleopLease::Change TeleopLeases::note(std::int64_t token_id, const msgs::Twist& command,
                                       int ttl_ms, TeleopLease::Clock::time_point now) {
  std::lock_guard lock(mutex_);
  const TeleopLease::Change change = leases_[token_id].note(command, ttl_ms, now);
  // A drive that is over needs no entry: the next command of its token starts a new one anyway.
  if (!leases_[token_id].running(now)) leases_.erase(token_id);
  return change;
}

}  // namespace mobot::api
