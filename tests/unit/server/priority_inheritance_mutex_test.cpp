#include "server/priority_inheritance_mutex.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

namespace mobot::server {
namespace {

TEST(PriorityInheritanceMutex, ExcludesASecondThreadUntilUnlocked) {
  PriorityInheritanceMutex mutex;
  std::atomic<bool> entered{false};
  mutex.lock();
  std::thread other([&] {
    std::lock_guard lock(mutex);
    entered = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_FALSE(entered.load()) << "the second thread got in while the first held the lock";
  mutex.unlock();
  other.join();
  EXPECT_TRUE(entered.load());
}

}  // namespace
}  // namespace mobot::server
