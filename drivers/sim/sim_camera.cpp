#include "drivers/sim/sim_camera.h"

#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

namespace mobot::sim {

SimCamera::SimCamera(double rate_hz, int jpeg_quality, std::function<RenderJob()> prepare)
    : rate_hz_(rate_hz),
      jpeg_quality_(jpeg_quality),
      prepare_(std::move(prepare)),
      schedule_(rate_hz > 0.0 ? 1.0 / rate_hz : 1.0) {
  if (!(rate_hz > 0.0) || jpeg_quality < 1 || jpeg_quality > 100) {
    throw std::invalid_argument("camera: rate_hz must be > 0 and jpeg_quality within 1..100");
  }
  thread_ = std::jthread([this](std::stop_token stop) { run(stop); });
}

SimCamera::~SimCamera() {
  thread_.request_stop();
  wake_.notify_all();
}

std::optional<msgs::Image> SimCamera::poll(double now_s) {
  std::optional<msgs::Image> frame;
  std::lock_guard lock(mutex_);
  frame.swap(ready_);
  if (schedule_.due(now_s) && !busy_) {
    schedule_.taken(now_s);
    job_ = prepare_();
    job_stamp_s_ = now_s;
    busy_ = true;
    wake_.notify_one();
  }
  return frame;
}

void SimCamera::run(std::stop_token stop) {
  std::unique_lock lock(mutex_);
  while (!stop.stop_requested()) {
    if (!wake_.wait(lock, stop, [this] { return job_.has_value(); })) return;
    RenderJob job = std::move(*job_);
    job_.reset();
    const double stamp_s = job_stamp_s_;
    lock.unlock();
    msgs::Image image;
    image.stamp_s = stamp_s;
    image.encoding = "jpeg";
    image.jpeg_quality = jpeg_quality_;
    const cv::Mat pixels = job();
    image.width = pixels.cols;
    image.height = pixels.rows;
    cv::imencode(".jpg", pixels, image.data, {cv::IMWRITE_JPEG_QUALITY, jpeg_quality_});
    lock.lock();
    ready_ = std::move(image);
    busy_ = false;
  }
}

}  // namespace mobot::sim
