#pragma once

#include <dirent.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "tools/emulate/device_line.h"
#include "tools/emulate/emulated_world.h"

namespace mobot::emulate::testing {

// One emulated device on a pty in a temporary directory, stepped every millisecond by its own
// thread: what a driver under test opens as its device.
class LineHarness {
 public:
  explicit LineHarness(std::unique_ptr<EmulatedDevice> device)
      : dir_(std::filesystem::temp_directory_path() /
             ("mobot-line-" + std::to_string(::getpid()) + "-" + std::to_string(++counter_))) {
    std::filesystem::create_directories(dir_);
    line_ = std::make_unique<DeviceLine>(std::move(device), dir_ / "device", 7);
    thread_ = std::jthread([this](const std::stop_token& stop) {
      while (!stop.stop_requested()) {
        {
          const std::lock_guard lock(mutex_);
          line_->step(seconds());
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    });
  }
  ~LineHarness() {
    thread_.request_stop();
    thread_.join();
    line_.reset();
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }

  std::filesystem::path path() const { return dir_ / "device"; }
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  // Runs `action` on the line between two steps.
  void with_line(const std::function<void(DeviceLine&)>& action) {
    const std::lock_guard lock(mutex_);
    action(*line_);
  }

 private:
  static inline int counter_ = 0;
  std::filesystem::path dir_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::mutex mutex_;
  std::unique_ptr<DeviceLine> line_;
  std::jthread thread_;
};

// A floor with nothing on it: every ray is a no-return; the base goes where it is put.
class EmptyWorld final : public EmulatedWorld {
 public:
  geometry::Pose2D base_pose() const override { return pose_; }
  void set_base_pose(const geometry::Pose2D& pose) override { pose_ = pose; }
  std::optional<double> cast_ray(geometry::Point2D, double, double, double) const override {
    return std::nullopt;
  }

 private:
  geometry::Pose2D pose_;
};

// An empty rectangular room: every ray from inside hits a wall.
class BoxWorld final : public EmulatedWorld {
 public:
  BoxWorld(double min_x, double max_x, double min_y, double max_y)
      : min_x_(min_x), max_x_(max_x), min_y_(min_y), max_y_(max_y) {}

  geometry::Pose2D base_pose() const override { return pose_; }
  void set_base_pose(const geometry::Pose2D& pose) override { pose_ = pose; }
  std::optional<double> cast_ray(geometry::Point2D from, double angle_rad, double /*height_m*/,
                                 double max_range_m) const override {
    const double dx = std::cos(angle_rad);
    const double dy = std::sin(angle_rad);
    double range_m = std::numeric_limits<double>::infinity();
    if (dx > 1e-12) range_m = std::min(range_m, (max_x_ - from.x) / dx);
    if (dx < -1e-12) range_m = std::min(range_m, (min_x_ - from.x) / dx);
    if (dy > 1e-12) range_m = std::min(range_m, (max_y_ - from.y) / dy);
    if (dy < -1e-12) range_m = std::min(range_m, (min_y_ - from.y) / dy);
    if (range_m > max_range_m) return std::nullopt;
    return range_m;
  }

 private:
  double min_x_;
  double max_x_;
  double min_y_;
  double max_y_;
  geometry::Pose2D pose_;
};

// The file descriptors this process holds now: a driver that leaks one per reconnect shows here.
inline int open_fd_count() {
  int count = 0;
  DIR* dir = ::opendir("/proc/self/fd");
  while (::readdir(dir) != nullptr) ++count;
  ::closedir(dir);
  return count;
}

// Polls `condition` every 5 ms for up to `timeout_s`.
inline bool eventually(const std::function<bool()>& condition, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < deadline) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return condition();
}

}  // namespace mobot::emulate::testing
