// Camera simulation cost on the built-in office: a 640 x 480 pinhole frame (target < 15 ms, so
// 15 fps fit on one core) and a 480 x 480 omni frame (target < 15 ms), with the default noise,
// two moving targets and an obstacle, from a rotating set of poses across the floor.
//   cmake --build build --target mobot_bench && ./build/tests/bench/mobot_bench
//   --benchmark_filter=Render

#include <benchmark/benchmark.h>

#include <filesystem>
#include <numbers>
#include <random>
#include <vector>

#include "core/vision/camera_pose.h"
#include "core/vision/omni_camera_model.h"
#include "drivers/sim/camera_noise.h"
#include "drivers/sim/camera_renderer.h"
#include "drivers/sim/camera_scene.h"
#include "drivers/sim/ray_caster.h"
#include "drivers/sim/world.h"

namespace mobot::sim {
namespace {

World office_world() {
  const std::filesystem::path worlds_dir = MOBOT_DEFAULT_WORLDS_DIR;
  return load_world(resolve_world(worlds_dir, "office"));
}

// Robot poses in free cells of the floor plan, so every frame starts where a robot could stand.
std::vector<geometry::Pose2D> free_poses(const mapping::OccupancyGrid& grid, int count) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> x_of(0.0, grid.width_m());
  std::uniform_real_distribution<double> y_of(0.0, grid.height_m());
  std::uniform_real_distribution<double> angle_of(-std::numbers::pi, std::numbers::pi);
  std::vector<geometry::Pose2D> poses;
  while (static_cast<int>(poses.size()) < count) {
    const geometry::Pose2D pose{grid.origin().x + x_of(rng), grid.origin().y + y_of(rng),
                                angle_of(rng)};
    const auto cell = grid.cell_at({pose.x, pose.y});
    if (cell && !grid.is_occupied(*cell)) poses.push_back(pose);
  }
  return poses;
}

// The office with things to look at: two targets in the west corridor and a pillar.
struct OfficeStage {
  World world = office_world();
  RayCaster walls{world.floor};
  std::vector<SceneCylinder> obstacles{{4.0, 7.0, 0.2, 0.8}};
  std::vector<SceneSphere> targets{{5.0, 7.8, 0.6, 0.15, {220, 30, 30}},
                                   {3.5, 7.2, 0.5, 0.12, {30, 200, 40}}};
  CameraScene scene() const { return {world, walls, obstacles, targets, {}}; }
};

void BM_RenderPerspectiveOffice(benchmark::State& state) {
  const OfficeStage stage;
  const CameraScene scene = stage.scene();
  const std::vector<geometry::Pose2D> poses = free_poses(stage.world.floor, 64);
  const vision::PinholeCamera camera;  // 640 x 480, 60 deg
  CameraNoise noise;
  std::mt19937_64 rng(1);
  noise.start(rng);
  std::size_t next = 0;
  for (auto _ : state) {
    const geometry::Pose2D& base = poses[next++ % poses.size()];
    noise.advance(1.0 / 15.0, rng);
    // The pan/tilt head 1.2 m up, tilted a little down.
    cv::Mat image =
        render_perspective(scene, {base.x, base.y, 1.2, base.theta, -0.1}, camera, noise, rng);
    benchmark::DoNotOptimize(image.data);
  }
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderPerspectiveOffice)->Unit(benchmark::kMillisecond);

// The rendering alone, without the noise.
void BM_RenderPerspectiveOfficeNoNoise(benchmark::State& state) {
  const OfficeStage stage;
  const CameraScene scene = stage.scene();
  const std::vector<geometry::Pose2D> poses = free_poses(stage.world.floor, 64);
  const CameraNoise noise = CameraNoise::none();
  std::mt19937_64 rng(1);
  std::size_t next = 0;
  for (auto _ : state) {
    const geometry::Pose2D& base = poses[next++ % poses.size()];
    cv::Mat image = render_perspective(scene, {base.x, base.y, 1.2, base.theta, -0.1},
                                       vision::PinholeCamera{}, noise, rng);
    benchmark::DoNotOptimize(image.data);
  }
}
BENCHMARK(BM_RenderPerspectiveOfficeNoNoise)->Unit(benchmark::kMillisecond);

void BM_RenderOmniOffice(benchmark::State& state) {
  const OfficeStage stage;
  const CameraScene scene = stage.scene();
  const std::vector<geometry::Pose2D> poses = free_poses(stage.world.floor, 64);
  const vision::OmniCameraModel model;  // 480 x 480
  CameraNoise noise;
  std::mt19937_64 rng(1);
  noise.start(rng);
  std::size_t next = 0;
  for (auto _ : state) {
    noise.advance(1.0 / 15.0, rng);
    cv::Mat image = render_omni(scene, poses[next++ % poses.size()], 1.0, model, noise, rng);
    benchmark::DoNotOptimize(image.data);
  }
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderOmniOffice)->Unit(benchmark::kMillisecond);

void BM_CameraNoise640x480(benchmark::State& state) {
  const CameraNoise noise;
  std::mt19937_64 rng(1);
  const cv::Mat clean(480, 640, CV_8UC3, cv::Scalar(90, 120, 150));
  cv::Mat image;
  for (auto _ : state) {
    clean.copyTo(image);
    noise.apply(image, rng);
    benchmark::DoNotOptimize(image.data);
  }
}
BENCHMARK(BM_CameraNoise640x480)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mobot::sim
