// Vision per frame: E6 target tracking (CamShift + Kalman) on 640 x 480 frames of a red disc
// crossing a textured, noisy scene (target < 10 ms, the source ran 7-10 fps on 2010 hardware), and
// E2's omni landmark bearing (unwarp + threshold + open + Hough) on a 480 x 480 omni frame with
// two red cylinders (target < 10 ms, E2 fuses at 10 Hz). Also the one-off cost of the unwarping
// maps. And the stream's camera_quality cap: one 640 x 480 frame of the camera (JPEG 80)
// compressed again at 30, which the hub does once per frame and cap in use.
//   cmake --build build --target mobot_bench && ./build/tests/bench/mobot_bench
//   --benchmark_filter=Vision

#include <benchmark/benchmark.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/vision/jpeg_requality.h"
#include "core/vision/omni_camera_model.h"
#include "core/vision/omni_landmark_bearing.h"
#include "core/vision/target_tracker.h"

namespace mobot::vision {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kFps = 15.0;

void add_noise(cv::Mat& image, cv::RNG& rng, double sigma) {
  cv::Mat noise(image.size(), CV_16SC3);
  rng.fill(noise, cv::RNG::NORMAL, 0, sigma);
  cv::Mat wide;
  image.convertTo(wide, CV_16SC3, 1.0 + rng.gaussian(0.05));
  wide += noise;
  wide.convertTo(image, CV_8UC3);
}

// A grey texture with coloured patches; a red disc of 30 px radius moving at (150, 20) px/s.
std::vector<cv::Mat> tracking_frames(int count) {
  cv::RNG rng(3);
  cv::Mat coarse(12, 16, CV_8UC1);
  rng.fill(coarse, cv::RNG::UNIFORM, 70, 190);
  cv::Mat grey;
  cv::resize(coarse, grey, {640, 480}, 0, 0, cv::INTER_CUBIC);
  cv::Mat background;
  cv::cvtColor(grey, background, cv::COLOR_GRAY2BGR);
  cv::rectangle(background, cv::Rect(30, 320, 130, 110), cv::Scalar(40, 160, 40), cv::FILLED);
  cv::rectangle(background, cv::Rect(500, 30, 110, 120), cv::Scalar(190, 90, 40), cv::FILLED);
  std::vector<cv::Mat> frames;
  for (int k = 0; k < count; ++k) {
    cv::Mat frame = background.clone();
    const double t = k / kFps;
    cv::circle(frame, {static_cast<int>(60 + 150 * t), static_cast<int>(200 + 20 * t)}, 30,
               cv::Scalar(40, 35, 205), cv::FILLED, cv::LINE_AA);
    add_noise(frame, rng, 7.0);
    frames.push_back(frame);
  }
  return frames;
}

void BM_VisionTargetTrackerFrame640x480(benchmark::State& state) {
  // 3.6 s of frames: the disc crosses most of the image; played forth and back.
  const std::vector<cv::Mat> frames = tracking_frames(54);
  TargetTracker tracker;
  if (tracker.start(frames.front(), {20, 160, 80, 80}, 0.0)) {
    state.SkipWithError("start() refused the seed box");
    return;
  }
  double stamp_s = 0.0;
  std::size_t k = 0;
  std::size_t tracking = 0;
  std::size_t updates = 0;
  for (auto _ : state) {
    const std::size_t cycle = 2 * frames.size() - 2;
    const std::size_t phase = ++k % cycle;
    const std::size_t index = phase < frames.size() ? phase : cycle - phase;
    stamp_s += 1.0 / kFps;
    const TrackState& result = tracker.update(frames[index], stamp_s);
    tracking += result.status == TrackStatus::kTracking ? 1 : 0;
    ++updates;
    benchmark::DoNotOptimize(result.centre_px);
  }
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["tracking_fraction"] = updates > 0 ? static_cast<double>(tracking) / updates : 0.0;
}
BENCHMARK(BM_VisionTargetTrackerFrame640x480)->Unit(benchmark::kMillisecond);

void BM_VisionJpegRequality640x480(benchmark::State& state) {
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", tracking_frames(1).front(), jpeg, {cv::IMWRITE_JPEG_QUALITY, 80});
  std::size_t bytes = 0;
  for (auto _ : state) {
    const auto smaller = requality_jpeg(jpeg, 30);
    bytes = smaller ? smaller->size() : 0;
    benchmark::DoNotOptimize(bytes);
  }
  state.counters["bytes_80"] = static_cast<double>(jpeg.size());
  state.counters["bytes_30"] = static_cast<double>(bytes);
}
BENCHMARK(BM_VisionJpegRequality640x480)->Unit(benchmark::kMillisecond);

// Floor and wall bands in grey with noise, and two red cylinders (2 m and 4 m away).
cv::Mat omni_frame(const OmniCameraModel& model) {
  cv::Mat image(model.height_px, model.width_px, CV_8UC3, cv::Scalar(45, 45, 45));
  const double horizon_px = model.radius_px(0.0);
  cv::circle(image, {240, 240}, static_cast<int>(model.radius_px(model.max_elevation_rad)),
             cv::Scalar(170, 175, 180), cv::FILLED);
  cv::circle(image, {240, 240}, static_cast<int>(horizon_px), cv::Scalar(120, 130, 140),
             cv::FILLED);
  cv::circle(image, {240, 240}, static_cast<int>(model.radius_px(model.min_elevation_rad)),
             cv::Scalar(45, 45, 45), cv::FILLED);
  for (const auto& [azimuth, range] : {std::pair{0.8, 2.0}, std::pair{-2.5, 4.0}}) {
    const double half = std::asin(0.05 / range);
    std::vector<cv::Point> outline;
    for (int i = 0; i <= 40; ++i) {
      const double e = -40 * kDeg + 55 * kDeg * i / 40;
      const auto p = model.project({azimuth + half, e});
      if (p) outline.emplace_back(static_cast<int>(p->u), static_cast<int>(p->v));
    }
    for (int i = 40; i >= 0; --i) {
      const double e = -40 * kDeg + 55 * kDeg * i / 40;
      const auto p = model.project({azimuth - half, e});
      if (p) outline.emplace_back(static_cast<int>(p->u), static_cast<int>(p->v));
    }
    cv::fillPoly(image, std::vector<std::vector<cv::Point>>{outline}, cv::Scalar(35, 30, 200),
                 cv::LINE_AA);
  }
  cv::RNG rng(5);
  add_noise(image, rng, 6.0);
  return image;
}

void BM_VisionOmniLandmarkBearing480(benchmark::State& state) {
  const OmniCameraModel model;
  const OmniLandmarkBearingDetector detector(model);
  const cv::Mat frame = omni_frame(model);
  std::size_t landmarks = 0;
  for (auto _ : state) {
    const OmniLandmarkDetection detection = detector.detect(frame);
    landmarks += detection.landmarks.size();
    benchmark::DoNotOptimize(detection.landmarks.data());
  }
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["landmarks"] =
      benchmark::Counter(static_cast<double>(landmarks), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_VisionOmniLandmarkBearing480)->Unit(benchmark::kMillisecond);

void BM_VisionOmniUnwarpOnly480(benchmark::State& state) {
  const OmniCameraModel model;
  const OmniLandmarkBearingDetector detector(model);
  const cv::Mat frame = omni_frame(model);
  for (auto _ : state) {
    const cv::Mat panorama = detector.unwarp(frame);
    benchmark::DoNotOptimize(panorama.data);
  }
}
BENCHMARK(BM_VisionOmniUnwarpOnly480)->Unit(benchmark::kMillisecond);

// Once per camera model: the remap tables (780 x 160 projections).
void BM_VisionOmniDetectorConstruction(benchmark::State& state) {
  const OmniCameraModel model;
  for (auto _ : state) {
    const OmniLandmarkBearingDetector detector(model);
    benchmark::DoNotOptimize(&detector);
  }
}
BENCHMARK(BM_VisionOmniDetectorConstruction)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mobot::vision
