#pragma once

#include <chrono>
#include <mutex>
#include <optional>
#include <stop_token>
#include <string>
#include <thread>

#include "core/msgs/image.h"
#include "drivers/device_status.h"
#include "drivers/serial/device_health.h"
#include "drivers/serial/reopen_backoff.h"

// OpenCV stays out of this header: only the camera's thread touches a cv::VideoCapture.
namespace cv {
class Mat;
class VideoCapture;
}  // namespace cv

namespace mobot::drivers::hardware {

struct OpenCvCameraOptions {
  // A V4L2 device ("/dev/video0", or its index "0"), a video file or an image sequence pattern
  // ("frames/frame_%03d.png"), or a stream URL ("rtsp://...", "http://...").
  std::string source;
  double rate_hz = 10.0;  // frames are kept no faster than this
  // The frame size wanted; 0: the source's. A device is asked for it, and frames of another
  // size (a file's, or a device's nearest mode) are scaled to it; with one of the two given the
  // other follows the source's aspect ratio.
  int width_px = 0;
  int height_px = 0;
  int jpeg_quality = 80;  // 1..100, cv::IMWRITE_JPEG_QUALITY
  serial::ReopenBackoffOptions backoff;
  // How long a stream may take to open or to deliver a frame before it counts as failed.
  double stream_timeout_s = 5.0;
};

// What a source string names, which decides the VideoCapture backend and what a failed read means.
enum class CameraSourceKind {
  kDevice,  // V4L2: a failed read is a fault
  kFile,    // any backend that reads it: the end of the file is not a fault, it plays again
  kStream,  // FFmpeg: a failed read is a fault
};
CameraSourceKind camera_source_kind(const std::string& source);

// A camera read through OpenCV's cv::VideoCapture on a thread of its own: opens the source, keeps
// its newest frame (JPEG-encoded, at most rate_hz of them) for take_frame(), and when the source
// is missing or stops delivering says so in the status, releases it and opens it again after the
// capped back-off of reopen_backoff.h. Counters: frames and JPEG bytes kept, reconnects.
class OpenCvCamera {
 public:
  // Throws std::invalid_argument for an empty source, a rate that is not positive, a negative
  // size or a JPEG quality outside 1..100.
  explicit OpenCvCamera(OpenCvCameraOptions options);
  ~OpenCvCamera();
  OpenCvCamera(const OpenCvCamera&) = delete;
  OpenCvCamera& operator=(const OpenCvCamera&) = delete;

  // Starts the thread (a no-op while it runs); stop() joins it. A backend blocked in a read
  // returns within its own time-out.
  void start();
  void stop();

  // The newest frame, if one came since the last call; its stamp is left for the caller.
  std::optional<msgs::Image> take_frame();
  // ok, or why not: "opening", "missing" (the source cannot be opened), "silent" (it opened but
  // gives no frames), "stopped".
  DeviceStatus status() const { return health_.status(); }
  DeviceCounters counters() const { return health_.counters(); }
  const OpenCvCameraOptions& options() const { return options_; }

 private:
  using Clock = std::chrono::steady_clock;
  enum class Outcome { kStopped, kEnded, kFailed };

  void run(const std::stop_token& stop);
  bool open(cv::VideoCapture& video) const;
  // Keeps frames from the open source until it fails, a file ends or `stop`; next_due is the
  // time the next frame may be kept, carried over from one opening to the next.
  Outcome play(cv::VideoCapture& video, const std::stop_token& stop, Clock::time_point& next_due);
  void keep(const cv::Mat& frame);
  void wait_until(const std::stop_token& stop, Clock::time_point deadline);

  const OpenCvCameraOptions options_;
  const CameraSourceKind kind_;
  serial::DeviceHealth health_{"camera"};
  std::mutex mutex_;
  std::optional<msgs::Image> newest_;
  std::jthread thread_;  // last: stopped and joined before the state it uses goes
};

}  // namespace mobot::drivers::hardware
