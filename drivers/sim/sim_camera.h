#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

#include <opencv2/core/mat.hpp>

#include "core/msgs/image.h"
#include "core/timing/rate_schedule.h"
#include "drivers/sensor_driver.h"

namespace mobot::sim {

// A simulated camera. Rendering a frame takes about 10 ms, half a control tick, so it happens on
// the camera's own thread, as a real camera exposes and encodes on its own: when a frame is due,
// poll() asks `prepare` (on the control loop) for a render job that holds a copy of everything the
// frame shows at that moment; the thread renders and JPEG-encodes it, and a later poll() returns
// it stamped with the moment it shows. At most one frame is in the works: a frame due while one
// renders is skipped, as a real camera drops frames its reader does not take.
class SimCamera final : public drivers::SensorDriver<msgs::Image> {
 public:
  using RenderJob = std::function<cv::Mat()>;

  // Throws std::invalid_argument for a rate that is not positive or a JPEG quality outside 1..100.
  SimCamera(double rate_hz, int jpeg_quality, std::function<RenderJob()> prepare);
  ~SimCamera() override;
  SimCamera(const SimCamera&) = delete;
  SimCamera& operator=(const SimCamera&) = delete;

  std::string_view name() const override { return "camera"; }
  double nominal_rate_hz() const override { return rate_hz_; }
  std::optional<msgs::Image> poll(double now_s) override;
  drivers::DeviceStatus status() const override { return {}; }

 private:
  void run(std::stop_token stop);

  const double rate_hz_;
  const int jpeg_quality_;
  std::function<RenderJob()> prepare_;
  timing::RateSchedule schedule_;

  std::mutex mutex_;
  std::condition_variable_any wake_;
  std::optional<RenderJob> job_;
  double job_stamp_s_ = 0.0;
  bool busy_ = false;
  std::optional<msgs::Image> ready_;
  std::jthread thread_;
};

}  // namespace mobot::sim
