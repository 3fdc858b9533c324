#pragma once

#include <memory>
#include <mutex>
#include <utility>

#include "server/priority_inheritance_mutex.h"

namespace mobot::server {

// The newest immutable value one thread (the control loop) publishes and any thread reads: a
// shared_ptr swapped under a priority-inheritance mutex, so that a reader never holds up the loop
// for longer than the copy of a pointer (see PriorityInheritanceMutex).
template <typename T>
class Latest {
 public:
  void store(std::shared_ptr<const T> value) {
    std::shared_ptr<const T> old;
    {
      std::lock_guard lock(mutex_);
      old = std::exchange(value_, std::move(value));
    }
    // `old` may be the last reference: destroyed outside the lock.
  }
  std::shared_ptr<const T> load() const {
    std::lock_guard lock(mutex_);
    return value_;
  }

 private:
  mutable PriorityInheritanceMutex mutex_;
  std::shared_ptr<const T> value_;
};

}  // namespace mobot::server
