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
  // A fixed camera looking ahead; tracking needs the frame size the driver delivers (frames are
  // scaled to width x height, so with both given it is known before the first frame).
  CameraInfo info;
  info.kind = "fixed";
  info.rate_hz = options.rate_hz;
  double fov_deg = 60.0;
  entry.number("horizontal_fov_deg", fov_deg, 10.0, 170.0);
  entry.done();
  // Without both sizes the frames keep the source's, unknown until the first: the camera
  // streams, but boxes for tracking need the size (GET /camera reports 0 x 0 then).
  info.pinhole = {options.width_px, options.height_px, fov_deg * 3.14159265358979323846 / 180.0};
  assembly.drivers.camera_info = info;

  auto device = std::make_unique<CameraDevice>(options);
  OpenCvCamera& camera = device->camera();
  assembly.drivers.camera = std::make_unique<PolledSensor<msgs::Image>>(
      "camera", options.rate_hz, [&camera] { return camera.take_frame(); },
      [&camera] { return camera.status(); });
  assembly.devices.push_back(std::move(device));
}

}  // namespace mobot::drivers::hardware
