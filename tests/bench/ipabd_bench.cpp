// IPaBD (docs/algorithms.md P2) on real-shaped clouds from the simulated nodding laser in the G2
// lobby: the source's 9 494-point sweep (94 scans x beams 40..140 deg at 1 deg) and a 1 000
// 000-point cloud (0.25 deg beams, 1 387 scans); targets < 2 ms and < 100 ms. Also one tilted
// scan's ray cast and its conversion to map-frame points, the per-scan cost on the control loop.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <numbers>

#include "core/perception/ipabd.h"
#include "core/perception/tilt_sweep.h"
#include "drivers/sim/simulator.h"
#include "drivers/sim/world.h"

namespace mobot {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

sim::Simulator lobby_simulator() {
  const std::filesystem::path worlds_dir = MOBOT_DEFAULT_WORLDS_DIR;
  return sim::Simulator(sim::load_world(sim::resolve_world(worlds_dir, "g2_lobby")),
                        sim::r1_profile(), 1);
}

// `scans` scans over the pitch range, keeping beams first_beam..last_beam of each.
perception::PointCloud lobby_cloud(int scans, double step_deg, std::size_t first_beam,
                                   std::size_t last_beam, std::size_t max_points) {
  sim::Simulator sim = lobby_simulator();
  perception::PointCloud cloud;
  cloud.reserve(max_points);
  for (int i = 0; i < scans && cloud.size() < max_points; ++i) {
    msgs::TiltScan scan =
        sim.read_tilt_laser(perception::assigned_pitch_rad(i, scans), step_deg * kDeg);
    scan.ranges_m.resize(std::min(scan.ranges_m.size(), last_beam + 1));
    for (std::size_t k = 0; k < first_beam; ++k) scan.ranges_m[k] = -1.0F;  // dropped
    perception::append_scan(scan, sim.true_pose(), cloud);
  }
  cloud.resize(std::min(cloud.size(), max_points));
  return cloud;
}

void run_ipabd(benchmark::State& state, const perception::PointCloud& cloud, double step_deg) {
  sim::Simulator sim = lobby_simulator();
  const geometry::Pose2D sensor = geometry::compose(sim.true_pose(), sim.profile().laser_in_base);
  perception::IpabdOptions options;
  options.bearing_step_rad = step_deg * kDeg;
  for (auto _ : state) {
    const perception::IpabdResult result =
        perception::run_ipabd(cloud, {sensor.x, sensor.y}, options);
    benchmark::DoNotOptimize(result.obstacles.cells().data());
  }
  state.counters["points"] = static_cast<double>(cloud.size());
}

void BM_Ipabd9494(benchmark::State& state) {
  const perception::PointCloud cloud = lobby_cloud(94, 1.0, 40, 140, 9494);
  run_ipabd(state, cloud, 1.0);
}
BENCHMARK(BM_Ipabd9494)->Unit(benchmark::kMicrosecond);

void BM_Ipabd1M(benchmark::State& state) {
  const perception::PointCloud cloud = lobby_cloud(1387, 0.25, 0, 720, 1'000'000);
  run_ipabd(state, cloud, 0.25);
}
BENCHMARK(BM_Ipabd1M)->Unit(benchmark::kMillisecond);

void BM_TiltScan721(benchmark::State& state) {
  sim::Simulator sim = lobby_simulator();
  perception::PointCloud cloud;
  cloud.reserve(800);
  for (auto _ : state) {
    cloud.clear();
    const msgs::TiltScan scan = sim.read_tilt_laser(5.0 * kDeg, 0.25 * kDeg);
    perception::append_scan(scan, sim.true_pose(), cloud);
    benchmark::DoNotOptimize(cloud.data());
  }
}
BENCHMARK(BM_TiltScan721)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace mobot
