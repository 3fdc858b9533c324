#include "drivers/serial/serial_port.h"

#include <sys/ioctl.h>
#include <termios.h>

#include <boost/asio/write.hpp>
#include <optional>

namespace mobot::drivers::serial {
namespace {

using boost::asio::serial_port_base;

std::string describe(const SerialOptions& options, const std::string& what,
                     const boost::system::error_code& error) {
  return options.device + ": " + what + ": " + error.message();
}

// Runs the io_context until `done` or `timeout`; on a time-out cancels the operation and runs
// its handler (with operation_aborted) so nothing is left pending.
template <class Done>
void run_until(boost::asio::io_context& io, boost::asio::serial_port& port,
               std::chrono::milliseconds timeout, const Done& done) {
  io.restart();
  io.run_for(timeout);
  if (!done()) {
    boost::system::error_code ignored;
    port.cancel(ignored);
    io.restart();
    io.run();
  }
}

}  // namespace

SerialPort::SerialPort(SerialOptions options) : options_(std::move(options)), port_(io_) {}

SerialPort::~SerialPort() { close(); }

void SerialPort::open() {
  close();
  boost::system::error_code error;
  port_.open(options_.device, error);
  if (error) throw SerialError(describe(options_, "cannot open", error));
  // Raw 8N1 without flow control; a pty accepts the same settings as a real line.
  port_.set_option(serial_port_base::baud_rate(options_.baud), error);
  if (!error) port_.set_option(serial_port_base::character_size(8), error);
  if (!error) port_.set_option(serial_port_base::parity(serial_port_base::parity::none), error);
  if (!error) {
    port_.set_option(serial_port_base::stop_bits(serial_port_base::stop_bits::one), error);
  }
  if (!error) {
    port_.set_option(serial_port_base::flow_control(serial_port_base::flow_control::none), error);
  }
  if (error) {
    close();
    throw SerialError(describe(options_, "is not a serial line", error));
  }
  if (options_.dtr) set_modem_line(TIOCM_DTR, *options_.dtr);
  if (options_.rts) set_modem_line(TIOCM_RTS, *options_.rts);
  discard_input();
}

void SerialPort::set_modem_line(int line, bool on) {
  // A pseudo-terminal has no modem lines (the ioctl fails there); a real adapter has them, and a
  // board that needs one simply stays silent without it, which the caller sees as a silent device.
  ::ioctl(port_.native_handle(), on ? TIOCMBIS : TIOCMBIC, &line);
}

void SerialPort::close() {
  if (!port_.is_open()) return;
  boost::system::error_code ignored;
  port_.cancel(ignored);
  port_.close(ignored);
}

void SerialPort::set_baud(unsigned baud) {
  boost::system::error_code error;
  port_.set_option(serial_port_base::baud_rate(baud), error);
  if (error)
    throw SerialError(describe(options_, "cannot set " + std::to_string(baud) + " baud", error));
  options_.baud = baud;
}

void SerialPort::discard_input() {
  if (port_.is_open()) ::tcflush(port_.native_handle(), TCIFLUSH);
}

std::size_t SerialPort::read_some(std::span<std::uint8_t> buffer,
                                  std::chrono::milliseconds timeout) {
  if (!port_.is_open()) throw SerialError(options_.device + ": not open");
  std::optional<boost::system::error_code> result;
  std::size_t received = 0;
  port_.async_read_some(boost::asio::buffer(buffer.data(), buffer.size()),
                        [&](const boost::system::error_code& error, std::size_t count) {
                          result = error;
                          received = count;
                        });
  run_until(io_, port_, timeout, [&] { return result.has_value(); });
  if (*result == boost::asio::error::operation_aborted) return received;
  if (*result) throw SerialError(describe(options_, "read failed", *result));
  return received;
}

void SerialPort::write_all(std::span<const std::uint8_t> bytes, std::chrono::milliseconds timeout) {
  if (!port_.is_open()) throw SerialError(options_.device + ": not open");
  std::optional<boost::system::error_code> result;
  boost::asio::async_write(
      port_, boost::asio::buffer(bytes.data(), bytes.size()),
      [&](const boost::system::error_code& error, std::size_t) { result = error; });
  run_until(io_, port_, timeout, [&] { return result.has_value(); });
  if (*result == boost::asio::error::operation_aborted) {
    throw SerialError(options_.device + ": write timed out");
  }
  if (*result) throw SerialError(describe(options_, "write failed", *result));
}

void SerialPort::write_all(std::string_view text, std::chrono::milliseconds timeout) {
  write_all(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), timeout);
}

}  // namespace mobot::drivers::serial
