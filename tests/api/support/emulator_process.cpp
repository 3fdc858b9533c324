#include "support/emulator_process.h"

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <stdexcept>
#include <vector>

#include "support/mobotd_process.h"

namespace mobot::testing {

EmulatorProcess::EmulatorProcess(const std::string& robot, std::uint64_t seed)
    : dir_(MobotdProcess::make_temp_dir()) {
  std::vector<std::string> args{MOBOT_EMULATE_PATH, robot,    "--dir",
                                dir_.string(),      "--seed", std::to_string(seed)};
  // Writing to an emulator that died must fail the test, not kill it.
  ::signal(SIGPIPE, SIG_IGN);
  int in_fds[2];
  int out_fds[2];
  if (::pipe(in_fds) != 0 || ::pipe(out_fds) != 0) throw std::runtime_error("pipe failed");
  pid_ = ::fork();
  if (pid_ == 0) {
    ::dup2(in_fds[0], STDIN_FILENO);
    ::dup2(out_fds[1], STDOUT_FILENO);
    ::close(in_fds[0]);
    ::close(in_fds[1]);
    ::close(out_fds[0]);
    ::close(out_fds[1]);
    std::vector<char*> argv;
    for (auto& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(in_fds[0]);
  ::close(out_fds[1]);
  stdin_fd_ = in_fds[1];
  stdout_fd_ = out_fds[0];
  for (std::string line = read_line(); line != "ready"; line = read_line()) {
    if (line.empty()) throw std::runtime_error("mobot-emulate did not start");
    if (line.starts_with("config ")) config_path_ = line.substr(7);
  }
}

EmulatorProcess::~EmulatorProcess() {
  if (stdin_fd_ >= 0) {
    const std::string quit = "quit\n";
    [[maybe_unused]] const ssize_t written = ::write(stdin_fd_, quit.data(), quit.size());
    ::close(stdin_fd_);
  }
  if (pid_ > 0) {
    int status = 0;
    for (int i = 0; i < 100 && ::waitpid(pid_, &status, WNOHANG) == 0; ++i) ::usleep(20000);
    if (::waitpid(pid_, &status, WNOHANG) == 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, &status, 0);
    }
  }
  if (stdout_fd_ >= 0) ::close(stdout_fd_);
  std::error_code ignored;
  std::filesystem::remove_all(dir_, ignored);
}

std::string EmulatorProcess::read_line() {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (true) {
    const auto newline = buffer_.find('\n');
    if (newline != std::string::npos) {
      std::string line = buffer_.substr(0, newline);
      buffer_.erase(0, newline + 1);
      return line;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return {};
    pollfd fd{stdout_fd_, POLLIN, 0};
    if (::poll(&fd, 1, static_cast<int>(left.count())) <= 0) return {};
    char chunk[512];
    const ssize_t count = ::read(stdout_fd_, chunk, sizeof chunk);
    if (count <= 0) return {};
    buffer_.append(chunk, static_cast<std::size_t>(count));
  }
}

std::string EmulatorProcess::command(const std::string& line) {
  const std::string text = line + "\n";
  if (::write(stdin_fd_, text.data(), text.size()) != static_cast<ssize_t>(text.size())) return {};
  return read_line();
}

}  // namespace mobot::testing
