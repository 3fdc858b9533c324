#pragma once

#include <sys/types.h>

#include <filesystem>
#include <map>
#include <string>

namespace mobot::testing {

// A mobot-emulate child process: a robot's devices on ptys in a temporary directory, and the
// hardware config it wrote for them. Commands go to its stdin, one answer line comes back.
class EmulatorProcess {
 public:
  explicit EmulatorProcess(const std::string& robot, std::uint64_t seed = 1);
  ~EmulatorProcess();
  EmulatorProcess(const EmulatorProcess&) = delete;
  EmulatorProcess& operator=(const EmulatorProcess&) = delete;

  const std::filesystem::path& config_path() const { return config_path_; }
  // Sends one command line; returns the answer line (empty when the process is gone).
  std::string command(const std::string& line);
  pid_t pid() const { return pid_; }

 private:
  std::string read_line();

  std::filesystem::path dir_;
  std::filesystem::path config_path_;
  pid_t pid_ = -1;
  int stdin_fd_ = -1;
  int stdout_fd_ = -1;
  std::string buffer_;
};

}  // namespace mobot::testing
