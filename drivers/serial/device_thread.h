#pragma once

#include <functional>
#include <stdexcept>
#include <stop_token>
#include <string>
#include <thread>

#include "drivers/serial/device_health.h"
#include "drivers/serial/reopen_backoff.h"
#include "drivers/serial/serial_port.h"

namespace mobot::drivers::serial {

// The device is there but does not speak as it should; `reason` is what /robot shows: "silent",
// "checksum", "garbage", "refused" (it answered a command with an error).
class DeviceFault : public std::runtime_error {
 public:
  explicit DeviceFault(const std::string& reason) : std::runtime_error(reason) {}
  std::string reason() const { return what(); }
};

// One device's thread: opens the line, runs the protocol session on it, and when the device is
// missing, vanishes (SerialError) or misbehaves (DeviceFault) records why in the health, closes
// the line and reopens it after a capped back-off, until stopped. The session marks the device
// ok in the health once it answered, and counts its frames; a session in which the device came
// good starts the back-off afresh.
class DeviceThread {
 public:
  // Runs with the line open until `stop` is requested (then returns) or the device fails
  // (then throws).
  using Session = std::function<void(SerialPort& port, const std::stop_token& stop)>;

  DeviceThread(SerialOptions options, DeviceHealth& health, Session session,
               ReopenBackoffOptions backoff = {});
  ~DeviceThread();
  DeviceThread(const DeviceThread&) = delete;
  DeviceThread& operator=(const DeviceThread&) = delete;

  void start();
  // Asks the session to return and joins the thread (the session's reads wake within their
  // time-outs).
  void stop();

 private:
  void run(const std::stop_token& stop);
  void wait(const std::stop_token& stop, double delay_s);

  SerialOptions options_;
  DeviceHealth& health_;
  Session session_;
  ReopenBackoff backoff_;
  std::jthread thread_;
};

}  // namespace mobot::drivers::serial
