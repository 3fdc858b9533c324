#pragma once

#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "core/msgs/image.h"
#include "core/vision/omni_landmark_bearing.h"

namespace mobot::server {

// What the detector found in one omni frame, stamped with the moment the frame shows.
struct OmniDetection {
  double stamp_s = 0.0;
  std::vector<vision::LandmarkBearing> landmarks;
};

// The omni camera's landmark detector (docs/algorithms.md E2, measurement 3 from pixels) off the
// control loop: a JPEG decode and the unwarp + Hough take about 4 ms a frame. The newest frame
// waiting replaces an older one; results are taken by the loop and never waited for.
class OmniBearingWorker {
 public:
  explicit OmniBearingWorker(const vision::OmniCameraModel& model);
  ~OmniBearingWorker();
  OmniBearingWorker(const OmniBearingWorker&) = delete;
  OmniBearingWorker& operator=(const OmniBearingWorker&) = delete;

  void submit(std::shared_ptr<const msgs::Image> frame);
  std::optional<OmniDetection> take_result();

 private:
  void run(std::stop_token stop);

  const vision::OmniLandmarkBearingDetector detector_;
  std::mutex mutex_;
  std::condition_variable_any wake_;
  std::shared_ptr<const msgs::Image> frame_;
  std::optional<OmniDetection> result_;
  std::jthread thread_;
};

}  // namespace mobot::server
