#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace mobot::testing {

// A real mobotd child process (sim backend, ephemeral port, its own data dir), started and waited
// for the way a user would: by its "mobotd listening on" line.
class MobotdProcess {
 public:
  struct Options {
    std::vector<std::string> extra_args;
    std::string backend = "sim";
    double time_scale = 10.0;
    std::filesystem::path data_dir;  // empty: a fresh temporary directory, removed at the end
    std::string token = "test-admin-token";
    // Both set: mobotd serves https and wss only (--tls-cert, --tls-key).
    std::filesystem::path tls_cert;
    std::filesystem::path tls_key;
    std::string log_level = "warn";
    // Where mobotd's stderr goes (its log); empty: the test's own stderr.
    std::filesystem::path stderr_file;
  };

  // A fresh temporary directory for a data dir that outlives one process (restart tests).
  static std::filesystem::path make_temp_dir();

  explicit MobotdProcess(Options options);
  MobotdProcess() : MobotdProcess(Options{}) {}
  ~MobotdProcess();
  MobotdProcess(const MobotdProcess&) = delete;
  MobotdProcess& operator=(const MobotdProcess&) = delete;

  std::uint16_t port() const { return port_; }
  const std::string& token() const { return options_.token; }
  const std::filesystem::path& data_dir() const { return data_dir_; }
  pid_t pid() const { return pid_; }
  std::chrono::milliseconds startup_time() const { return startup_time_; }

  // SIGTERM and wait; returns the exit status (or -1 on a signal death).
  int terminate();
  // SIGKILL: the process gets no chance to flush anything.
  void kill_hard();
  // True while the child runs (it has not exited or crashed).
  bool alive();
  std::string base_url() const {
    return std::string(secure_ ? "https" : "http") + "://127.0.0.1:" + std::to_string(port_);
  }
  // The ready line said https.
  bool secure() const { return secure_; }

 private:
  void start();

  Options options_;
  std::filesystem::path data_dir_;
  bool owns_data_dir_ = false;
  pid_t pid_ = -1;
  int stdout_fd_ = -1;
  std::uint16_t port_ = 0;
  bool secure_ = false;
  std::chrono::milliseconds startup_time_{0};
};

}  // namespace mobot::testing
