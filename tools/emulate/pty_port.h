#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace mobot::emulate {

// An emulated device's end of a serial line: a pseudo-terminal whose other end appears at
// `link_path` (a symbolic link, as a USB adapter appears under /dev/serial/by-id), raw 8N1 like a
// real line. Unplugging closes both ends, so a driver's reads fail as on a pulled USB cable, and
// removes the link; plugging in again makes a new pty at the same link.
class PtyPort {
 public:
  explicit PtyPort(std::filesystem::path link_path);
  ~PtyPort();
  PtyPort(const PtyPort&) = delete;
  PtyPort& operator=(const PtyPort&) = delete;

  const std::filesystem::path& link_path() const { return link_path_; }
  // The pty's own name (/dev/pts/N), or empty while unplugged.
  const std::string& device_name() const { return device_name_; }
  bool plugged() const { return master_fd_ >= 0; }

  void unplug();
  void plug();

  // What the host wrote since the last call (nothing while unplugged).
  std::size_t read(std::span<std::uint8_t> buffer);
  // Sends what the line takes now; the rest is dropped, as a device's bytes are when nobody
  // listens. Returns how many bytes went out.
  std::size_t write(std::span<const std::uint8_t> bytes);

 private:
  std::filesystem::path link_path_;
  std::string device_name_;
  int master_fd_ = -1;
  // Held open so the line keeps its settings and the master does not see a hang-up between two
  // opens by the driver.
  int slave_fd_ = -1;
};

}  // namespace mobot::emulate
