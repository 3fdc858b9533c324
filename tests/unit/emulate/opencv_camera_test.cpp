// The camera's factory against sources written on the spot: a short MJPG video, a folder of
// images, a file that is not there yet. The real cv::VideoCapture reads them.
#include "drivers/hardware/opencv_camera.h"

#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <string>
#include <thread>

#include "drivers/hardware/camera_devices.h"
#include "drivers/sim/robot_profile.h"
#include "tests/unit/emulate/line_harness.h"

namespace mobot::drivers::hardware {
namespace {

using emulate::testing::eventually;

constexpr int kWidth_px = 160;
constexpr int kHeight_px = 120;
constexpr int kVideoFrames = 10;

// A frame that differs from its neighbours: a bar that moves along a grey ramp.
cv::Mat test_frame(int index) {
  cv::Mat frame(kHeight_px, kWidth_px, CV_8UC3);
  for (int row = 0; row < kHeight_px; ++row) {
    frame.row(row).setTo(cv::Scalar(row * 2, 100, 255 - row * 2));
  }
  frame.colRange(index * 10, index * 10 + 10).setTo(cv::Scalar(255, 255, 255));
  return frame;
}

// Written beside its path and renamed into place, so the camera never opens half a file.
void write_video(const std::filesystem::path& path) {
  const std::filesystem::path staged = path.parent_path() / ("staged-" + path.filename().string());
  {
    // OpenCV's own MJPEG writer: there whatever codecs the system's FFmpeg has.
    cv::VideoWriter writer(staged.string(), cv::CAP_OPENCV_MJPEG,
                           cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 25.0,
                           cv::Size(kWidth_px, kHeight_px));
    ASSERT_TRUE(writer.isOpened());
    for (int i = 0; i < kVideoFrames; ++i) writer.write(test_frame(i));
  }
  std::filesystem::rename(staged, path);
}

HardwareAssembly assembly_of(const sim::RobotProfile& profile, const BackendOptions& options) {
  return HardwareAssembly{profile, options, {}, {}, nullptr, {}};
}

class OpenCvCameraTest : public ::testing::Test {
 protected:
  OpenCvCameraTest()
      : dir_(std::filesystem::temp_directory_path() /
             ("mobot-camera-" + std::to_string(::getpid()) + "-" +
              ::testing::UnitTest::GetInstance()->current_test_info()->name())) {
    std::filesystem::create_directories(dir_);
  }
  ~OpenCvCameraTest() override {
    for (const auto& device : assembly_.devices) device->stop();
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }

  // The entry as the backend hands it over: `driver` already read.
  void make(const std::string& source, const std::string& extra = "") {
    const YAML::Node node = YAML::Load("{driver: opencv, source: '" + source + "'" + extra + "}");
    DeviceReader entry(node, "hardware.camera");
    std::string driver;
    entry.text("driver", driver);
    make_opencv_camera(entry, assembly_);
  }
  void start() {
    for (const auto& device : assembly_.devices) device->start();
  }
  SensorDriver<msgs::Image>& camera() { return *assembly_.drivers.camera; }
  DeviceCounters counters() const { return assembly_.devices.at(0)->counters().at(0); }

  std::optional<msgs::Image> next_frame(double timeout_s = 5.0) {
    std::optional<msgs::Image> image;
    eventually([&] { return (image = camera().poll(7.5)).has_value(); }, timeout_s);
    return image;
  }

  std::string error_of(const std::string& yaml) {
    HardwareAssembly assembly = assembly_of(profile_, options_);
    const YAML::Node node = YAML::Load(yaml);
    DeviceReader entry(node, "hardware.camera");
    try {
      make_opencv_camera(entry, assembly);
    } catch (const BackendError& error) {
      return error.what();
    }
    return "";
  }

  std::filesystem::path dir_;
  sim::RobotProfile profile_ = sim::r1_profile();
  BackendOptions options_;
  HardwareAssembly assembly_ = assembly_of(profile_, options_);
};

TEST_F(OpenCvCameraTest, TheSourceKindPicksTheBackend) {
  EXPECT_EQ(camera_source_kind("/dev/video0"), CameraSourceKind::kDevice);
  EXPECT_EQ(camera_source_kind("/dev/video7"), CameraSourceKind::kDevice);
  EXPECT_EQ(camera_source_kind("0"), CameraSourceKind::kDevice);
  EXPECT_EQ(camera_source_kind("/dev/null"), CameraSourceKind::kDevice);
  EXPECT_EQ(camera_source_kind("rtsp://192.168.1.10:554/stream"), CameraSourceKind::kStream);
  EXPECT_EQ(camera_source_kind("http://camera.local/video.mjpg"), CameraSourceKind::kStream);
  EXPECT_EQ(camera_source_kind("videos/hall.avi"), CameraSourceKind::kFile);
  EXPECT_EQ(camera_source_kind("frames/frame_%03d.png"), CameraSourceKind::kFile);
}

TEST_F(OpenCvCameraTest, FramesOfAVideoArriveAsJpeg) {
  const std::filesystem::path video = dir_ / "hall.avi";
  write_video(video);
  make(video.string(), ", rate_hz: 20, jpeg_quality: 90");
  EXPECT_EQ(camera().name(), "camera");
  EXPECT_EQ(camera().nominal_rate_hz(), 20.0);
  start();
  const std::optional<msgs::Image> image = next_frame();
  ASSERT_TRUE(image) << camera().status().reason;
  EXPECT_TRUE(camera().status().ok) << camera().status().reason;
  EXPECT_EQ(image->stamp_s, 7.5);
  EXPECT_EQ(image->encoding, "jpeg");
  EXPECT_EQ(image->width, kWidth_px);
  EXPECT_EQ(image->height, kHeight_px);
  const cv::Mat decoded = cv::imdecode(image->data, cv::IMREAD_COLOR);
  ASSERT_FALSE(decoded.empty());
  EXPECT_EQ(decoded.cols, kWidth_px);
  EXPECT_EQ(decoded.rows, kHeight_px);
  // The picture survives two JPEG passes: the ramp's bottom row is still mostly blue (BGR).
  const cv::Vec3b pixel = decoded.at<cv::Vec3b>(kHeight_px - 1, kWidth_px - 1);
  EXPECT_GT(pixel[0], 200);
  EXPECT_LT(pixel[2], 60);

  const DeviceCounters counted = counters();
  EXPECT_EQ(counted.name, "camera");
  EXPECT_TRUE(counted.status.ok);
  EXPECT_GE(counted.frames, 1u);
  EXPECT_GE(counted.bytes, image->data.size());
  EXPECT_EQ(counted.reconnects, 0u);
}

TEST_F(OpenCvCameraTest, TheRateHoldsAndAFileThatEndedPlaysAgain) {
  const std::filesystem::path video = dir_ / "hall.avi";
  write_video(video);
  make(video.string(), ", rate_hz: 20");
  start();
  ASSERT_TRUE(next_frame()) << camera().status().reason;
  const std::uint64_t before = counters().frames;
  int polled = 0;
  const auto started = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - started < std::chrono::milliseconds(1500)) {
    if (camera().poll(1.0)) ++polled;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  // 30 frames at 20 Hz from a file of 10: it looped, read at the rate and not as fast as
  // the file decodes.
  const std::uint64_t kept = counters().frames - before;
  EXPECT_NEAR(static_cast<double>(kept), 30.0, 4.0);
  EXPECT_NEAR(polled, 30, 5);
  EXPECT_TRUE(camera().status().ok) << camera().status().reason;
  // Playing the file again is not a reconnect.
  EXPECT_EQ(counters().reconnects, 0u);
}

TEST_F(OpenCvCameraTest, FramesAreScaledToTheConfiguredSize) {
  const std::filesystem::path video = dir_ / "hall.avi";
  write_video(video);
  make(video.string(), ", width: 80, height: 40");
  start();
  std::optional<msgs::Image> image = next_frame();
  ASSERT_TRUE(image) << camera().status().reason;
  EXPECT_EQ(image->width, 80);
  EXPECT_EQ(image->height, 40);
  const cv::Mat decoded = cv::imdecode(image->data, cv::IMREAD_COLOR);
  EXPECT_EQ(decoded.size(), cv::Size(80, 40));
}

TEST_F(OpenCvCameraTest, OneSideGivenKeepsTheAspectRatio) {
  const std::filesystem::path video = dir_ / "hall.avi";
  write_video(video);
  make(video.string(), ", width: 80");
  start();
  std::optional<msgs::Image> image = next_frame();
  ASSERT_TRUE(image) << camera().status().reason;
  EXPECT_EQ(image->width, 80);
  EXPECT_EQ(image->height, 60);
}

TEST_F(OpenCvCameraTest, AnImageSequenceIsASource) {
  for (int i = 0; i < 4; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%03d.png", i);
    ASSERT_TRUE(cv::imwrite((dir_ / name).string(), test_frame(i)));
  }
  make((dir_ / "frame_%03d.png").string(), ", rate_hz: 20");
  start();
  const std::optional<msgs::Image> image = next_frame();
  ASSERT_TRUE(image) << camera().status().reason;
  const cv::Mat decoded = cv::imdecode(image->data, cv::IMREAD_COLOR);
  EXPECT_EQ(decoded.size(), cv::Size(kWidth_px, kHeight_px));
  // Four images, and more frames than that: the sequence plays again too.
  EXPECT_TRUE(eventually([&] { return counters().frames > 8; }, 3.0)) << counters().frames;
  EXPECT_TRUE(camera().status().ok) << camera().status().reason;
}

TEST_F(OpenCvCameraTest, AMissingSourceIsMissingUntilItAppears) {
  const std::filesystem::path video = dir_ / "later.avi";
  make(video.string());
  start();
  ASSERT_TRUE(eventually(
      [&] {
        const DeviceStatus status = camera().status();
        return !status.ok && status.reason == "missing";
      },
      2.0))
      << camera().status().reason;
  EXPECT_FALSE(camera().poll(1.0));
  // Long enough for the back-off to have grown past its first step.
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  write_video(video);
  // Found within the back-off's cap (2 s).
  const std::optional<msgs::Image> image = next_frame(4.0);
  ASSERT_TRUE(image) << camera().status().reason;
  EXPECT_EQ(image->width, kWidth_px);
  EXPECT_TRUE(camera().status().ok);
  EXPECT_EQ(counters().reconnects, 1u);
}

TEST_F(OpenCvCameraTest, AFileThatIsNoVideoIsMissing) {
  // OpenCV cannot open it at all: to the camera that is the same as not finding it.
  const std::filesystem::path junk = dir_ / "junk.avi";
  {
    std::FILE* file = std::fopen(junk.c_str(), "wb");
    ASSERT_NE(file, nullptr);
    std::fputs("this is not a video", file);
    std::fclose(file);
  }
  make(junk.string());
  start();
  EXPECT_TRUE(eventually([&] { return camera().status().reason == "missing"; }, 3.0))
      << camera().status().reason;
}

TEST_F(OpenCvCameraTest, AnAbsentDeviceIsMissingAndStopSaysStopped) {
  make("/dev/video-mobot-test-absent");
  start();
  EXPECT_TRUE(eventually([&] { return camera().status().reason == "missing"; }, 2.0))
      << camera().status().reason;
  assembly_.devices.at(0)->stop();
  EXPECT_EQ(camera().status().reason, "stopped");
}

TEST_F(OpenCvCameraTest, BadOptionsAreNamed) {
  EXPECT_EQ(error_of("{source: /dev/video0}"), "");
  const auto error_names = [&](const std::string& yaml, const std::string& key) {
    const std::string error = error_of(yaml);
    EXPECT_NE(error.find(key), std::string::npos) << yaml << " gave '" << error << "'";
  };
  error_names("{rate_hz: 10}", "hardware.camera.source: required");
  error_names("{source: [1, 2]}", "hardware.camera.source:");
  error_names("{source: /dev/video0, rate_hz: 0}", "hardware.camera.rate_hz:");
  error_names("{source: /dev/video0, width: -1}", "hardware.camera.width:");
  error_names("{source: /dev/video0, height: 100000}", "hardware.camera.height:");
  error_names("{source: /dev/video0, jpeg_quality: 101}", "hardware.camera.jpeg_quality:");
  error_names("{source: /dev/video0, fps: 30}", "hardware.camera.fps: unknown key");
}

}  // namespace
}  // namespace mobot::drivers::hardware
