#include "api/camera_requality.h"

#include "core/vision/jpeg_requality.h"

namespace mobot::api {

CameraRequality::CameraRequality(Done done)
    : done_(std::move(done)), thread_([this](const std::stop_token& stop) { run(stop); }) {}

void CameraRequality::submit(msgs::Image image, const FrameStamp& stamp,
                             std::vector<int> qualities) {
  {
    std::lock_guard lock(mutex_);
    job_ = Job{std::move(image), stamp, std::move(qualities)};
  }
  wake_.notify_one();
}

void CameraRequality::run(const std::stop_token& stop) {
  std::unique_lock lock(mutex_);
  while (!stop.stop_requested()) {
    if (!wake_.wait(lock, stop, [this] { return job_.has_value(); })) return;
    Job job = std::move(*job_);
    job_.reset();
    lock.unlock();
    std::vector<std::pair<int, msgs::Image>> variants;
    for (const int quality : job.qualities) {
      auto jpeg = vision::requality_jpeg(job.image.data, quality);
      // A frame that does not decode reaches nobody in a lower quality, as it would reach
      // nobody in its own.
      if (!jpeg) continue;
      msgs::Image variant;
      variant.stamp_s = job.image.stamp_s;
      variant.width = job.image.width;
      variant.height = job.image.height;
      variant.encoding = job.image.encoding;
      variant.jpeg_quality = quality;
      variant.data = std::move(*jpeg);
      variants.emplace_back(quality, std::move(variant));
    }
    if (!variants.empty()) done_(job.stamp, std::move(variants));
    lock.lock();
  }
}

}  // namespace mobot::api
