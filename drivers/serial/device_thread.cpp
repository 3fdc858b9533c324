#include "drivers/serial/device_thread.h"

#include <condition_variable>
#include <mutex>

#include <spdlog/spdlog.h>

namespace mobot::drivers::serial {

DeviceThread::DeviceThread(SerialOptions options, DeviceHealth& health, Session session,
                           ReopenBackoffOptions backoff)
    : options_(std::move(options)),
      health_(health),
      session_(std::move(session)),
      backoff_(backoff) {}

DeviceThread::~DeviceThread() { stop(); }

void DeviceThread::start() {
  thread_ = std::jthread([this](const std::stop_token& stop) { run(stop); });
}

void DeviceThread::stop() {
  if (!thread_.joinable()) return;
  thread_.request_stop();
  thread_.join();
}

void DeviceThread::wait(const std::stop_token& stop, double delay_s) {
  std::mutex mutex;
  std::condition_variable_any woken;
  std::unique_lock lock(mutex);
  woken.wait_for(lock, stop, std::chrono::duration<double>(delay_s), [] { return false; });
}

void DeviceThread::run(const std::stop_token& stop) {
  SerialPort port(options_);
  bool failed_before = false;
  std::string last_reason;
  while (!stop.stop_requested()) {
    std::string reason;
    const std::uint64_t recoveries_before = health_.recoveries();
    try {
      port.open();
      if (failed_before) health_.add_reconnect();
      session_(port, stop);
    } catch (const SerialError& error) {
      // Not there, or gone: a USB adapter unplugged fails its reads with EIO.
      reason = "missing";
      if (reason != last_reason) spdlog::warn("{}: {}", health_.name(), error.what());
    } catch (const DeviceFault& fault) {
      reason = fault.reason();
      if (reason != last_reason) {
        spdlog::warn("{}: {} on {}", health_.name(), reason, options_.device);
      }
    }
    port.close();
    if (stop.stop_requested()) break;
    health_.set_fault(reason);
    failed_before = true;
    last_reason = reason;
    if (health_.recoveries() != recoveries_before) backoff_.reset();
    wait(stop, backoff_.next_delay_s());
  }
  health_.set_fault("stopped");
}

}  // namespace mobot::drivers::serial
