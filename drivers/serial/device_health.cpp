#include "drivers/serial/device_health.h"

namespace mobot::drivers::serial {

void DeviceHealth::set_fault(std::string reason) {
  const std::lock_guard lock(mutex_);
  status_ = {false, std::move(reason)};
}

void DeviceHealth::set_ok() {
  const std::lock_guard lock(mutex_);
  if (!status_.ok) recoveries_.fetch_add(1, std::memory_order_relaxed);
  status_ = {};
}

DeviceStatus DeviceHealth::status() const {
  const std::lock_guard lock(mutex_);
  return status_;
}

DeviceCounters DeviceHealth::counters() const {
  return {name_, status(), bytes(), frames(), checksum_errors(), reconnects(), std::nullopt};
}

}  // namespace mobot::drivers::serial
