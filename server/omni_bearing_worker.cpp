#include "server/omni_bearing_worker.h"

#include <opencv2/imgcodecs.hpp>

namespace mobot::server {

OmniBearingWorker::OmniBearingWorker(const vision::OmniCameraModel& model) : detector_(model) {
  thread_ = std::jthread([this](std::stop_token stop) { run(stop); });
}

OmniBearingWorker::~OmniBearingWorker() {
  thread_.request_stop();
  wake_.notify_all();
}

void OmniBearingWorker::submit(std::shared_ptr<const msgs::Image> frame) {
  std::lock_guard lock(mutex_);
  frame_ = std::move(frame);
  wake_.notify_one();
}

std::optional<OmniDetection> OmniBearingWorker::take_result() {
  std::lock_guard lock(mutex_);
  std::optional<OmniDetection> out;
  out.swap(result_);
  return out;
}

void OmniBearingWorker::run(std::stop_token stop) {
  std::unique_lock lock(mutex_);
  while (!stop.stop_requested()) {
    if (!wake_.wait(lock, stop, [this] { return frame_ != nullptr; })) return;
    std::shared_ptr<const msgs::Image> frame = std::move(frame_);
    frame_.reset();
    lock.unlock();
    OmniDetection detection{frame->stamp_s, {}};
    if (frame->encoding == "jpeg") {
      const cv::Mat bgr = cv::imdecode(
          cv::Mat(1, static_cast<int>(frame->data.size()), CV_8UC1,
                  const_cast<std::uint8_t*>(frame->data.data())),
          cv::IMREAD_COLOR);
      if (!bgr.empty()) detection.landmarks = detector_.detect(bgr).landmarks;
    }
    lock.lock();
    result_ = std::move(detection);
  }
}

}  // namespace mobot::server
