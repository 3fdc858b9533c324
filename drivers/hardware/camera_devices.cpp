#include "drivers/hardware/camera_devices.h"

#include <memory>
#include <utility>

#include "drivers/hardware/opencv_camera.h"
#include "drivers/hardware/polled_sensor.h"

namespace mobot::drivers::hardware {
namespace {

class CameraDevice final : public HardwareDevice {
 public:
  explicit CameraDevice(OpenCvCameraOptions options) : camera_(std::move(options)) {}
  void start() override { camera_.start(); }
  void stop() override { camera_.stop(); }
  std::vector<DeviceCounters> counters() const override { return {camera_.counters()}; }
  OpenCvCamera& camera() { return camera_; }

 private:
  OpenCvCamera camera_;
};

}  // namespace

void make_opencv_camera(DeviceReader& entry, HardwareAssembly& assembly) {
  OpenCvCameraOptions options;
  entry.text("source", options.source);
  if (options.source.empty()) {
    throw BackendError(entry.path() +
                       ".source: required (/dev/video0, a device index, a video file, an image "
                       "pattern such as frames/frame_%03d.png, or a stream URL)");
  }
  entry.number("rate_hz", options.rate_hz, 0.1, 120.0);
  entry.integer("width", options.width_px, 0, 16384);
  entry.integer("height", options.height_px, 0, 16384);
  entry.integer("jpeg_quality", options.jpeg_quality, 1, 100);
  entry.done();

  auto device = std::make_unique<CameraDevice>(options);
  OpenCvCamera& camera = device->camera();
  assembly.drivers.camera = std::make_unique<PolledSensor<msgs::Image>>(
      "camera", options.rate_hz, [&camera] { return camera.take_frame(); },
      [&camera] { return camera.status(); });
  assembly.devices.push_back(std::move(device));
}

}  // namespace mobot::drivers::hardware
