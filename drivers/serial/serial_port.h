#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/serial_port.hpp>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

namespace mobot::drivers::serial {

// The line settings of one device. Every device mobot drives speaks 8N1 without flow control.
struct SerialOptions {
  std::string device;  // any path: a tty, a USB-serial symlink, a pty
  unsigned baud = 115200;
  // Some boards read these lines: the YDLIDAR's motor enable is DTR, an Arduino resets when DTR
  // falls. Unset: left as the kernel opens them.
  std::optional<bool> dtr;
  std::optional<bool> rts;
};

// The device vanished, refused to open or failed a read or write; what() says which and why.
class SerialError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A serial line with time-outs, on Asio's serial_port. Blocking calls for one device thread: a
// read waits at most its time-out, so the thread notices a silent device and a stop request.
class SerialPort {
 public:
  explicit SerialPort(SerialOptions options);
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  // Opens and configures the line, dropping whatever the kernel buffered before. Throws
  // SerialError when the device is missing or is not a serial line.
  void open();
  void close();
  bool is_open() const { return port_.is_open(); }
  const SerialOptions& options() const { return options_; }

  // Waits up to `timeout` for at least one byte; returns how many arrived (0: none in time).
  // Throws SerialError when the device fails (unplugged: EIO).
  std::size_t read_some(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout);
  // Writes everything or throws SerialError (also when the line takes longer than `timeout`).
  void write_all(std::span<const std::uint8_t> bytes, std::chrono::milliseconds timeout);
  void write_all(std::string_view text, std::chrono::milliseconds timeout);
  // Changes the line's speed on the open port (a device told to switch its baud rate).
  void set_baud(unsigned baud);
  // Drops bytes received and not yet read (a reply that came after its time-out).
  void discard_input();

 private:
  void set_modem_line(int line, bool on);

  SerialOptions options_;
  boost::asio::io_context io_;
  boost::asio::serial_port port_;
};

// The time `bytes` take on a line of `baud` (10 bits per byte: start, 8 data, stop).
constexpr double line_time_s(std::size_t bytes, unsigned baud) {
  return static_cast<double>(bytes) * 10.0 / static_cast<double>(baud);
}

}  // namespace mobot::drivers::serial
