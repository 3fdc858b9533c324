#include "api/operator_lock.h"

namespace mobot::api {

OperatorLock::OperatorLock(std::chrono::milliseconds dead_man) : dead_man_(dead_man) {}

bool OperatorLock::lapsed_locked(Clock::time_point now) const {
  return holder_ && now - last_command_ > dead_man_;
}

DomainError OperatorLock::busy_locked() const {
  const Claimant& holder = holder_->claimant;
  return {ErrorKind::kConflict, "operator_busy",
          "the robot is driven by " + (holder.caller.label.empty() ? "another operator"
                                                                   : holder.caller.label) +
              " (token " + std::to_string(holder.caller.token_id) +
              "); ask them to release it, or an admin may take over"};
}

Result<OperatorHolder> OperatorLock::acquire(const Claimant& who, Clock::time_point now,
                                             double now_unix_s) {
  std::lock_guard lock(mutex_);
  if (lapsed_locked(now)) holder_.reset();
  if (holder_ && holder_->claimant.caller.token_id != who.caller.token_id) return busy_locked();
  if (!holder_) holder_ = OperatorHolder{who, now_unix_s};
  last_command_ = now;
  return *holder_;
}

Result<Done> OperatorLock::release(const Claimant& who, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  if (lapsed_locked(now)) holder_.reset();
  if (!holder_) return Done{};
  if (holder_->claimant.caller.token_id != who.caller.token_id) {
    return DomainError{ErrorKind::kConflict, "not_holder",
                       "the operator lock is held by somebody else: only they (or an admin's "
                       "take_over) can let it go"};
  }
  holder_.reset();
  return Done{};
}

Result<OperatorHolder> OperatorLock::take_over(const Claimant& who, Clock::time_point now,
                                               double now_unix_s) {
  std::lock_guard lock(mutex_);
  if (!holder_ || holder_->claimant.caller.token_id != who.caller.token_id) {
    holder_ = OperatorHolder{who, now_unix_s};
  }
  last_command_ = now;
  return *holder_;
}

Result<OperatorHolder> OperatorLock::command(const Claimant& who, Clock::time_point now,
                                             double now_unix_s) {
  auto change = claim(who, now, now_unix_s);
  if (!change.ok()) return change.error();
  return change.value().after;
}

Result<OperatorLock::Change> OperatorLock::claim(const Claimant& who, Clock::time_point now,
                                                 double now_unix_s) {
  std::lock_guard lock(mutex_);
  if (lapsed_locked(now)) holder_.reset();
  if (holder_ && holder_->claimant.caller.token_id != who.caller.token_id) return busy_locked();
  Change change{{}, holder_, last_command_};
  if (!holder_) {
    holder_ = OperatorHolder{who, now_unix_s};
  } else {
    holder_->claimant.client_id = who.client_id;
    holder_->claimant.stream = who.stream;
    holder_->claimant.address = who.address;
  }
  last_command_ = now;
  change.after = *holder_;
  return change;
}

void OperatorLock::undo(const Change& change) {
  std::lock_guard lock(mutex_);
  const auto same = [](const OperatorHolder& a, const OperatorHolder& b) {
    return a.claimant.caller.token_id == b.claimant.caller.token_id &&
           a.claimant.client_id == b.claimant.client_id && a.since_unix_s == b.since_unix_s;
  };
  if (!holder_ || !same(*holder_, change.after)) return;
  holder_ = change.before;
  last_command_ = change.before_last_command;
}

void OperatorLock::connection_closed(std::uint64_t client_id) {
  std::lock_guard lock(mutex_);
  if (holder_ && holder_->claimant.stream && holder_->claimant.client_id == client_id) {
    holder_.reset();
  }
}

std::optional<OperatorHolder> OperatorLock::holder(Clock::time_point now) const {
  std::lock_guard lock(mutex_);
  if (lapsed_locked(now)) return std::nullopt;
  return holder_;
}

}  // namespace mobot::api
