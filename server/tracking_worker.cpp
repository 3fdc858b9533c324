#include "server/tracking_worker.h"

#include <opencv2/imgcodecs.hpp>

namespace mobot::server {
namespace {

cv::Mat decoded(const msgs::Image& image) {
  if (image.encoding == "jpeg") {
    return cv::imdecode(cv::Mat(1, static_cast<int>(image.data.size()), CV_8UC1,
                                const_cast<std::uint8_t*>(image.data.data())),
                        cv::IMREAD_COLOR);
  }
  if (image.encoding == "bgr8" && image.width > 0 && image.height > 0 &&
      image.data.size() == static_cast<std::size_t>(image.width) * image.height * 3) {
    return cv::Mat(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.data.data()))
        .clone();
  }
  return {};
}

}  // namespace

TrackingWorker::TrackingWorker(vision::TargetTrackerOptions options) : tracker_(options) {
  thread_ = std::jthread([this](std::stop_token stop) { run(stop); });
}

TrackingWorker::~TrackingWorker() {
  thread_.request_stop();
  wake_.notify_all();
}

void TrackingWorker::start(std::shared_ptr<const msgs::Image> frame, cv::Rect box,
                           Started started) {
  std::lock_guard lock(mutex_);
  start_ = StartJob{std::move(frame), box, std::move(started)};
  frame_.reset();
  result_.reset();
  stop_requested_ = false;
  wake_.notify_one();
}

void TrackingWorker::stop() {
  std::lock_guard lock(mutex_);
  stop_requested_ = true;
  frame_.reset();
  result_.reset();
  wake_.notify_one();
}

void TrackingWorker::submit(std::shared_ptr<const msgs::Image> frame, vision::PanTilt head,
                            std::optional<double> range_m) {
  std::lock_guard lock(mutex_);
  frame_ = FrameJob{std::move(frame), head, range_m};
  wake_.notify_one();
}

std::optional<TrackedFrame> TrackingWorker::take_result() {
  std::lock_guard lock(mutex_);
  std::optional<TrackedFrame> out;
  out.swap(result_);
  return out;
}

void TrackingWorker::run(std::stop_token stop) {
  std::unique_lock lock(mutex_);
  while (!stop.stop_requested()) {
    if (!wake_.wait(lock, stop, [this] { return start_ || frame_ || stop_requested_; })) return;
    if (stop_requested_) {
      stop_requested_ = false;
      tracker_.stop();
      continue;
    }
    if (start_) {
      StartJob job = std::move(*start_);
      start_.reset();
      lock.unlock();
      do_start(job);
      lock.lock();
      continue;
    }
    FrameJob job = std::move(*frame_);
    frame_.reset();
    lock.unlock();
    do_frame(job);
    lock.lock();
  }
}

void TrackingWorker::do_start(StartJob& job) {
  const cv::Mat bgr = decoded(*job.frame);
  std::optional<vision::TrackerError> error =
      bgr.empty() ? std::optional(vision::TrackerError::kInvalidFrame)
                  : tracker_.start(bgr, job.box, job.frame->stamp_s);
  job.started(error, tracker_.state());
}

void TrackingWorker::do_frame(const FrameJob& job) {
  if (tracker_.state().status == vision::TrackStatus::kIdle) return;
  const cv::Mat bgr = decoded(*job.frame);
  if (bgr.empty()) return;
  TrackedFrame result{tracker_.update(bgr, job.frame->stamp_s), job.frame->stamp_s, job.head,
                      job.range_m};
  // A frame refused for its stamp (one that came before the start frame) reports nothing.
  if (result.state.frame_error == vision::TrackerError::kInvalidStamp) return;
  std::lock_guard lock(mutex_);
  // A stop or a new start since this frame was taken makes its result stale.
  if (stop_requested_ || start_) return;
  result_ = std::move(result);
}

}  // namespace mobot::server
