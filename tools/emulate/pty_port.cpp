#include "tools/emulate/pty_port.h"

#include <fcntl.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace mobot::emulate {

PtyPort::PtyPort(std::filesystem::path link_path) : link_path_(std::move(link_path)) { plug(); }

PtyPort::~PtyPort() { unplug(); }

void PtyPort::plug() {
  if (plugged()) return;
  std::array<char, 128> name{};
  termios raw{};
  cfmakeraw(&raw);
  cfsetispeed(&raw, B115200);
  cfsetospeed(&raw, B115200);
  if (::openpty(&master_fd_, &slave_fd_, name.data(), &raw, nullptr) != 0) {
    throw std::runtime_error("openpty: " + std::string(std::strerror(errno)));
  }
  ::fcntl(master_fd_, F_SETFL, ::fcntl(master_fd_, F_GETFL) | O_NONBLOCK);
  device_name_ = name.data();
  std::error_code ignored;
  std::filesystem::remove(link_path_, ignored);
  std::filesystem::create_symlink(device_name_, link_path_);
}

void PtyPort::unplug() {
  if (!plugged()) return;
  std::error_code ignored;
  std::filesystem::remove(link_path_, ignored);
  ::close(slave_fd_);
  ::close(master_fd_);
  slave_fd_ = -1;
  master_fd_ = -1;
  device_name_.clear();
}

std::size_t PtyPort::read(std::span<std::uint8_t> buffer) {
  if (!plugged()) return 0;
  const ssize_t count = ::read(master_fd_, buffer.data(), buffer.size());
  return count > 0 ? static_cast<std::size_t>(count) : 0;
}

std::size_t PtyPort::write(std::span<const std::uint8_t> bytes) {
  if (!plugged() || bytes.empty()) return 0;
  const ssize_t count = ::write(master_fd_, bytes.data(), bytes.size());
  return count > 0 ? static_cast<std::size_t>(count) : 0;
}

}  // namespace mobot::emulate
