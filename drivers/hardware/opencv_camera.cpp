#include "drivers/hardware/opencv_camera.h"

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <stdexcept>
#include <system_error>
#include <utility>
#include <vector>

#include <spdlog/spdlog.h>

namespace mobot::drivers::hardware {
namespace {

bool all_digits(const std::string& text) {
  return !text.empty() &&
         std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

bool exists(const std::string& path) {
  std::error_code ignored;
  return std::filesystem::exists(path, ignored);
}

OpenCvCameraOptions checked(OpenCvCameraOptions options) {
  if (options.source.empty()) throw std::invalid_argument("camera: no source");
  if (!(options.rate_hz > 0.0) || !std::isfinite(options.rate_hz)) {
    throw std::invalid_argument("camera: the rate must be positive");
  }
  if (options.width_px < 0 || options.height_px < 0) {
    throw std::invalid_argument("camera: a negative frame size");
  }
  if (options.jpeg_quality < 1 || options.jpeg_quality > 100) {
    throw std::invalid_argument("camera: the JPEG quality is 1..100");
  }
  if (!(options.stream_timeout_s > 0.0)) {
    throw std::invalid_argument("camera: the stream time-out must be positive");
  }
  return options;
}

// The size frames are kept at: the configured one, the other side following the source's aspect
// ratio when only one is given, or the source's own.
cv::Size kept_size(const OpenCvCameraOptions& options, const cv::Size& frame) {
  if (options.width_px > 0 && options.height_px > 0) return {options.width_px, options.height_px};
  if (options.width_px > 0) {
    const double scale = static_cast<double>(options.width_px) / frame.width;
    return {options.width_px, std::max(1, static_cast<int>(std::lround(frame.height * scale)))};
  }
  if (options.height_px > 0) {
    const double scale = static_cast<double>(options.height_px) / frame.height;
    return {std::max(1, static_cast<int>(std::lround(frame.width * scale))), options.height_px};
  }
  return frame;
}

}  // namespace

CameraSourceKind camera_source_kind(const std::string& source) {
  if (source.find("://") != std::string::npos) return CameraSourceKind::kStream;
  if (all_digits(source)) return CameraSourceKind::kDevice;
  // A /dev path is a device even while it is unplugged (and so not there to look at).
  std::error_code ignored;
  if (source.starts_with("/dev/") || std::filesystem::is_character_file(source, ignored)) {
    return CameraSourceKind::kDevice;
  }
  return CameraSourceKind::kFile;
}

OpenCvCamera::OpenCvCamera(OpenCvCameraOptions options)
    : options_(checked(std::move(options))), kind_(camera_source_kind(options_.source)) {}

OpenCvCamera::~OpenCvCamera() { stop(); }

void OpenCvCamera::start() {
  if (thread_.joinable()) return;
  thread_ = std::jthread([this](const std::stop_token& stop) { run(stop); });
}

void OpenCvCamera::stop() {
  if (!thread_.joinable()) return;
  thread_.request_stop();
  thread_.join();
}

std::optional<msgs::Image> OpenCvCamera::take_frame() {
  const std::lock_guard lock(mutex_);
  return std::exchange(newest_, std::nullopt);
}

bool OpenCvCamera::open(cv::VideoCapture& video) const {
  const std::string& source = options_.source;
  try {
    switch (kind_) {
      case CameraSourceKind::kDevice:
        if (all_digits(source)) return video.open(std::stoi(source), cv::CAP_V4L2);
        if (!exists(source)) return false;
        if (!video.open(source, cv::CAP_V4L2)) return false;
        // A request: the driver picks its nearest mode, and keep() scales what differs.
        if (options_.width_px > 0) video.set(cv::CAP_PROP_FRAME_WIDTH, options_.width_px);
        if (options_.height_px > 0) video.set(cv::CAP_PROP_FRAME_HEIGHT, options_.height_px);
        return true;
      case CameraSourceKind::kStream: {
        const int timeout_ms = static_cast<int>(std::lround(options_.stream_timeout_s * 1e3));
        // Only FFmpeg takes these: another backend given a parameter it does not know refuses
        // to open.
        return video.open(source, cv::CAP_FFMPEG,
                          {cv::CAP_PROP_OPEN_TIMEOUT_MSEC, timeout_ms,
                           cv::CAP_PROP_READ_TIMEOUT_MSEC, timeout_ms});
      }
      case CameraSourceKind::kFile:
        // Asking every backend about a file that is not there would log a warning from each of
        // them at every retry. A pattern ("frame_%03d.png") names no file of its own.
        if (source.find('%') == std::string::npos && !exists(source)) return false;
        return video.open(source, cv::CAP_ANY);
    }
  } catch (const std::exception& error) {
    spdlog::debug("camera: opening {}: {}", source, error.what());
  }
  return false;
}

void OpenCvCamera::keep(const cv::Mat& frame) {
  const cv::Size size = kept_size(options_, frame.size());
  cv::Mat scaled;
  if (size != frame.size()) cv::resize(frame, scaled, size, 0.0, 0.0, cv::INTER_AREA);
  const cv::Mat& out = scaled.empty() ? frame : scaled;
  std::vector<std::uint8_t> jpeg;
  if (!cv::imencode(".jpg", out, jpeg, {cv::IMWRITE_JPEG_QUALITY, options_.jpeg_quality})) {
    throw cv::Exception(cv::Error::StsError, "the frame does not encode as JPEG", __func__,
                        __FILE__, __LINE__);
  }
  health_.add_frame();
  health_.add_bytes(jpeg.size());
  health_.set_ok();
  msgs::Image image;
  image.width = out.cols;
  image.height = out.rows;
  image.encoding = "jpeg";
  image.jpeg_quality = options_.jpeg_quality;
  image.data = std::move(jpeg);
  const std::lock_guard lock(mutex_);
  newest_ = std::move(image);
}

OpenCvCamera::Outcome OpenCvCamera::play(cv::VideoCapture& video, const std::stop_token& stop,
                                         Clock::time_point& next_due) {
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(1.0 / options_.rate_hz));
  const bool live = kind_ != CameraSourceKind::kFile;
  std::uint64_t frames = 0;
  cv::Mat frame;
  while (!stop.stop_requested()) {
    if (live) {
      // Every frame is taken off a live source as it comes, kept or not: the driver's buffers
      // would otherwise fill and the frame kept later be seconds old.
      if (!video.grab()) return Outcome::kFailed;
      if (Clock::now() < next_due) continue;
      if (!video.retrieve(frame) || frame.empty()) return Outcome::kFailed;
    } else {
      // A file gives its frames as fast as they are read: it is read at the rate instead.
      wait_until(stop, next_due);
      if (stop.stop_requested()) break;
      if (!video.read(frame) || frame.empty()) {
        return frames > 0 ? Outcome::kEnded : Outcome::kFailed;
      }
    }
    keep(frame);
    ++frames;
    // On the grid of the period, so a camera whose frames do not fall on it still gives the
    // rate on average; after a stall the grid starts again rather than catching up in a burst.
    const Clock::time_point now = Clock::now();
    next_due += period;
    if (next_due <= now) next_due = now + period;
  }
  return Outcome::kStopped;
}

void OpenCvCamera::run(const std::stop_token& stop) {
  serial::ReopenBackoff backoff(options_.backoff);
  bool failed_before = false;
  std::string last_reason;
  Clock::time_point next_due = Clock::now();
  while (!stop.stop_requested()) {
    const std::uint64_t recoveries_before = health_.recoveries();
    std::string reason = "missing";
    cv::VideoCapture video;
    if (open(video)) {
      if (failed_before) health_.add_reconnect();
      Outcome outcome = Outcome::kFailed;
      try {
        outcome = play(video, stop, next_due);
      } catch (const std::exception& error) {
        spdlog::debug("camera: reading {}: {}", options_.source, error.what());
      }
      video.release();
      if (outcome == Outcome::kStopped) break;
      // A file that ended plays again from its start, at once and without a fault: what a user
      // testing with a recorded video wants is a camera that keeps running.
      if (outcome == Outcome::kEnded) continue;
      reason = "silent";
    }
    if (stop.stop_requested()) break;
    health_.set_fault(reason);
    if (reason != last_reason) spdlog::warn("camera: {} ({})", reason, options_.source);
    failed_before = true;
    last_reason = reason;
    // A source that came good since the last failure starts the back-off afresh.
    if (health_.recoveries() != recoveries_before) backoff.reset();
    wait_until(stop, Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(backoff.next_delay_s())));
  }
  health_.set_fault("stopped");
}

void OpenCvCamera::wait_until(const std::stop_token& stop, Clock::time_point deadline) {
  std::mutex mutex;
  std::condition_variable_any woken;
  std::unique_lock lock(mutex);
  woken.wait_until(lock, stop, deadline, [] { return false; });
}

}  // namespace mobot::drivers::hardware
