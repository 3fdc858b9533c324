#pragma once

#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "core/msgs/image.h"
#include "core/vision/pan_tilt_head.h"
#include "core/vision/target_tracker.h"

namespace mobot::server {

// What the tracker made of one frame, with what the head and the ranger said when it was taken.
struct TrackedFrame {
  vision::TrackState state;
  double stamp_s = 0.0;
  vision::PanTilt head;
  std::optional<double> range_m;
};

// CamShift + Kalman (docs/algorithms.md E6) off the control loop: decoding a JPEG and tracking
// take about 4 ms a frame at 640 x 480, a fifth of a tick. The loop hands frames in and takes
// results out and never waits; a frame that arrives while one is in work replaces the waiting one
// (only the newest matters to a tracker that coasts on its prediction).
class TrackingWorker {
 public:
  using Started = std::function<void(std::optional<vision::TrackerError>, const vision::TrackState&)>;

  explicit TrackingWorker(vision::TargetTrackerOptions options = {});
  ~TrackingWorker();
  TrackingWorker(const TrackingWorker&) = delete;
  TrackingWorker& operator=(const TrackingWorker&) = delete;

  // Seeds the tracker with `box` on `frame` (the image the user drew on) on the worker thread;
  // `started` is called there with the tracker's refusal or its first state. Frames submitted
  // before are dropped.
  void start(std::shared_ptr<const msgs::Image> frame, cv::Rect box, Started started);
  void stop();
  void submit(std::shared_ptr<const msgs::Image> frame, vision::PanTilt head,
              std::optional<double> range_m);
  // The newest result since the last call.
  std::optional<TrackedFrame> take_result();

 private:
  struct StartJob {
    std::shared_ptr<const msgs::Image> frame;
    cv::Rect box;
    Started started;
  };
  struct FrameJob {
    std::shared_ptr<const msgs::Image> frame;
    vision::PanTilt head;
    std::optional<double> range_m;
  };
  void run(std::stop_token stop);
  void do_start(StartJob& job);
  void do_frame(const FrameJob& job);

  vision::TargetTracker tracker_;  // the worker thread's alone
  std::mutex mutex_;
  std::condition_variable_any wake_;
  std::optional<StartJob> start_;
  std::optional<FrameJob> frame_;
  bool stop_requested_ = false;
  std::optional<TrackedFrame> result_;
  std::jthread thread_;
};

}  // namespace mobot::server
