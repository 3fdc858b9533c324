#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

#include "drivers/device_status.h"

namespace mobot::drivers::serial {

// What a device thread knows about its device, read by the control loop (status) and /metrics
// (counters) on other threads.
class DeviceHealth {
 public:
  explicit DeviceHealth(std::string name) : name_(std::move(name)) {}

  const std::string& name() const { return name_; }

  void set_fault(std::string reason);
  void set_ok();
  // How many times the device came good (a fault, then set_ok): a reopen that got this far
  // starts the back-off afresh.
  std::uint64_t recoveries() const { return recoveries_.load(std::memory_order_relaxed); }
  DeviceStatus status() const;

  void add_bytes(std::size_t count) { bytes_.fetch_add(count, std::memory_order_relaxed); }
  // A complete frame, reply or scan: what the rate on /metrics counts.
  void add_frame() { frames_.fetch_add(1, std::memory_order_relaxed); }
  void add_checksum_error() { checksum_errors_.fetch_add(1, std::memory_order_relaxed); }
  void add_reconnect() { reconnects_.fetch_add(1, std::memory_order_relaxed); }

  std::uint64_t bytes() const { return bytes_.load(std::memory_order_relaxed); }
  std::uint64_t frames() const { return frames_.load(std::memory_order_relaxed); }
  std::uint64_t checksum_errors() const { return checksum_errors_.load(std::memory_order_relaxed); }
  std::uint64_t reconnects() const { return reconnects_.load(std::memory_order_relaxed); }
  DeviceCounters counters() const;

 private:
  std::string name_;
  mutable std::mutex mutex_;
  DeviceStatus status_{false, "opening"};
  std::atomic<std::uint64_t> bytes_{0};
  std::atomic<std::uint64_t> frames_{0};
  std::atomic<std::uint64_t> checksum_errors_{0};
  std::atomic<std::uint64_t> reconnects_{0};
  std::atomic<std::uint64_t> recoveries_{0};
};

}  // namespace mobot::drivers::serial
