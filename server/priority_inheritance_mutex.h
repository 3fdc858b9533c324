#pragma once

#include <pthread.h>

namespace mobot::server {

// A mutex with priority inheritance, for state the real-time control loop shares with the
// network threads. With a plain lock (or a spinlock such as std::atomic<std::shared_ptr>'s) a
// reader preempted while holding it makes the loop wait until the scheduler comes back to the
// reader, which takes a hundred milliseconds with 50 busy clients on two cores. Here the holder
// runs at the loop's priority until it unlocks. BasicLockable, for std::lock_guard.
class PriorityInheritanceMutex {
 public:
  PriorityInheritanceMutex();
  ~PriorityInheritanceMutex();
  PriorityInheritanceMutex(const PriorityInheritanceMutex&) = delete;
  PriorityInheritanceMutex& operator=(const PriorityInheritanceMutex&) = delete;

  void lock();
  void unlock();

 private:
  pthread_mutex_t mutex_;
};

}  // namespace mobot::server
