#include "support/mobotd_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <random>
#include <stdexcept>
#include <thread>

namespace mobot::testing {
namespace {

std::filesystem::path fresh_temp_dir() {
  std::random_device random;
  const auto dir = std::filesystem::temp_directory_path() /
                   ("mobotd-test-" + std::to_string(::getpid()) + "-" + std::to_string(random()));
  std::filesystem::create_directories(dir);
  return dir;
}

int wait_for_exit(pid_t pid, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  int status = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return -2;
}

}  // namespace

MobotdProcess::MobotdProcess(Options options) : options_(std::move(options)) {
  data_dir_ = options_.data_dir;
  if (data_dir_.empty()) {
    data_dir_ = fresh_temp_dir();
    owns_data_dir_ = true;
  }
  try {
    start();
  } catch (...) {
    // The destructor does not run for a constructor that throws: clean up here.
    if (stdout_fd_ >= 0) ::close(stdout_fd_);
    if (owns_data_dir_) {
      std::error_code ignored;
      std::filesystem::remove_all(data_dir_, ignored);
    }
    throw;
  }
}

MobotdProcess::~MobotdProcess() {
  if (pid_ > 0) terminate();
  if (stdout_fd_ >= 0) ::close(stdout_fd_);
  if (owns_data_dir_) {
    std::error_code ignored;
    std::filesystem::remove_all(data_dir_, ignored);
  }
}

void MobotdProcess::start() {
  std::vector<std::string> args{MOBOTD_PATH,
                                "--backend",
                                options_.backend,
                                "--port",
                                "0",
                                "--bind",
                                "127.0.0.1",
                                "--time-scale",
                                std::to_string(options_.time_scale),
                                "--data-dir",
                                data_dir_.string(),
                                "--token",
                                options_.token,
                                "--log-level",
                                options_.log_level};
  if (!options_.tls_cert.empty()) {
    args.insert(args.end(), {"--tls-cert", options_.tls_cert.string()});
  }
  if (!options_.tls_key.empty()) args.insert(args.end(), {"--tls-key", options_.tls_key.string()});
  args.insert(args.end(), options_.extra_args.begin(), options_.extra_args.end());
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) throw std::runtime_error("pipe failed");
  const auto started = std::chrono::steady_clock::now();
  pid_ = ::fork();
  if (pid_ == 0) {
    if (!options_.stderr_file.empty()) {
      const int log_fd = ::open(options_.stderr_file.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0600);
      if (log_fd >= 0) {
        ::dup2(log_fd, STDERR_FILENO);
        ::close(log_fd);
      }
    }
    ::dup2(pipe_fds[1], STDOUT_FILENO);
    ::close(pipe_fds[0]);
    ::close(pipe_fds[1]);
    std::vector<char*> argv;
    for (auto& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(pipe_fds[1]);
  stdout_fd_ = pipe_fds[0];

  std::string output;
  // "mobotd listening on http://ADDR:PORT", or https:// when TLS is on.
  const std::string marker = "mobotd listening on ";
  const auto deadline = started + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd poll_fd{stdout_fd_, POLLIN, 0};
    if (::poll(&poll_fd, 1, 100) <= 0) continue;
    char buffer[512];
    const ssize_t n = ::read(stdout_fd_, buffer, sizeof buffer);
    if (n <= 0) break;
    output.append(buffer, static_cast<std::size_t>(n));
    const auto at = output.find(marker);
    const auto end = at == std::string::npos ? at : output.find('\n', at);
    if (end != std::string::npos) {
      const std::string address = output.substr(at + marker.size(), end - at - marker.size());
      secure_ = address.rfind("https://", 0) == 0;
      port_ = static_cast<std::uint16_t>(std::stoi(address.substr(address.rfind(':') + 1)));
      startup_time_ = std::chrono::duration_cast<std::chrono::milliseconds>(
          std::chrono::steady_clock::now() - started);
      // Keep draining stdout so the child never blocks on a full pipe.
      ::fcntl(stdout_fd_, F_SETFL, O_NONBLOCK);
      return;
    }
  }
  kill_hard();
  throw std::runtime_error("mobotd did not print its listening line; output: " + output);
}

std::filesystem::path MobotdProcess::make_temp_dir() { return fresh_temp_dir(); }

bool MobotdProcess::alive() {
  if (pid_ <= 0) return false;
  int status = 0;
  const pid_t done = ::waitpid(pid_, &status, WNOHANG);
  if (done == pid_) {
    pid_ = -1;
    return false;
  }
  return true;
}

int MobotdProcess::terminate() {
  if (pid_ <= 0) return -1;
  ::kill(pid_, SIGTERM);
  const int status = wait_for_exit(pid_, std::chrono::seconds(10));
  pid_ = -1;
  return status;
}

void MobotdProcess::kill_hard() {
  if (pid_ <= 0) return;
  ::kill(pid_, SIGKILL);
  int status = 0;
  ::waitpid(pid_, &status, 0);
  pid_ = -1;
}

}  // namespace mobot::testing
