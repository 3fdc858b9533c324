// docs/algorithms.md E4 timings: one particle-filter update (motion, 60-beam likelihood-field
// weighting, KLD resampling, clustering) with 2000 particles on the built-in office map, target
// < 2 ms; its parts; a global-localization update (50000 particles); preparing a map.
//   cmake --build build --target mobot_bench && ./build/tests/bench/mobot_bench
//   --benchmark_filter=ParticleFilter
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <vector>

#include "core/estimation/particle_filter/beam_likelihood.h"
#include "core/estimation/particle_filter/kld_sampler.h"
#include "core/estimation/particle_filter/particle_clusters.h"
#include "core/estimation/particle_filter/particle_filter.h"
#include "drivers/sim/ray_caster.h"
#include "drivers/sim/world.h"

namespace mobot::estimation {
namespace {

using geometry::Pose2D;

constexpr int kBeams = 361;  // R1's laser: 0.5 deg over 180 deg, thinned to 60 by the model
constexpr double kIncrement_rad = std::numbers::pi / (kBeams - 1);

const sim::World& office() {
  static const sim::World world =
      sim::load_world(sim::resolve_world(MOBOT_DEFAULT_WORLDS_DIR, "office"));
  return world;
}

// The robot driving the office's corridor (y = 7.5 m) east and back in 0.3 m steps: a pose and
// the scan it sees, so every update moves by more than update_min_translation_m.
struct Corridor {
  std::vector<Pose2D> poses;
  std::vector<msgs::LaserScan> scans;
};

const Corridor& corridor() {
  static const Corridor run = [] {
    Corridor c;
    const sim::RayCaster caster(office().floor);
    for (double x = 2.0; x <= 18.0; x += 0.3) c.poses.push_back({x, 7.5, 0.0});
    for (double x = 18.0; x >= 2.0; x -= 0.3) c.poses.push_back({x, 7.5, std::numbers::pi});
    for (const Pose2D& pose : c.poses) {
      msgs::LaserScan scan;
      scan.angle_min_rad = static_cast<float>(-std::numbers::pi / 2.0);
      scan.angle_increment_rad = static_cast<float>(kIncrement_rad);
      scan.range_min_m = 0.1F;
      scan.range_max_m = 30.0F;
      std::vector<double> ranges(kBeams);
      caster.cast_fan({pose.x, pose.y}, pose.theta - std::numbers::pi / 2.0, kIncrement_rad, 30.0,
                      ranges);
      for (const double r : ranges) scan.ranges_m.push_back(static_cast<float>(r));
      c.scans.push_back(std::move(scan));
    }
    return c;
  }();
  return run;
}

const ParticleFilterMap& office_map() {
  static const ParticleFilterMap map = prepare_particle_filter_map(office().floor);
  return map;
}

// Odometry that follows the truth (the motion model adds the noise), turning on the spot at the
// corridor's ends.
void run_updates(benchmark::State& state, ParticleFilter& filter) {
  const Corridor& run = corridor();
  std::size_t next = 1;
  std::size_t particles = 0;
  for (auto _ : state) {
    const std::size_t i = next++ % run.poses.size();
    const FilterUpdate outcome = filter.update(run.poses[i], &run.scans[i]);
    benchmark::DoNotOptimize(outcome);
    particles += filter.particles().size();
  }
  state.counters["particles"] =
      static_cast<double>(particles) / static_cast<double>(state.iterations());
  state.counters["beams"] = static_cast<double>(filter.last_beam_count());
}

void BM_ParticleFilterUpdate2000(benchmark::State& state) {
  ParticleFilterOptions options;
  options.kld.max_particles = options.kld.min_particles = 2000;
  ParticleFilter filter(options);
  filter.set_map(office_map());
  filter.initialize(corridor().poses.front(), Eigen::Vector3d(0.01, 0.01, 0.003).asDiagonal(),
                    corridor().poses.front());
  run_updates(state, filter);
}
BENCHMARK(BM_ParticleFilterUpdate2000)->Unit(benchmark::kMillisecond);

// The defaults (KLD between 2000 and 5000) while tracking: the tight cloud needs the minimum.
void BM_ParticleFilterUpdateKldTracking(benchmark::State& state) {
  ParticleFilter filter;
  filter.set_map(office_map());
  filter.initialize(corridor().poses.front(), Eigen::Vector3d(0.01, 0.01, 0.003).asDiagonal(),
                    corridor().poses.front());
  run_updates(state, filter);
}
BENCHMARK(BM_ParticleFilterUpdateKldTracking)->Unit(benchmark::kMillisecond);

// The first update after global initialisation: global_particles (50000) over the whole office,
// weighed over successive calls of at most max_weighed_per_update particles (the control ticks
// that carry it). The time is the whole weighing; `calls` the ticks it takes and
// `longest_call_ms` the most one of them carries.
void BM_ParticleFilterGlobalUpdate(benchmark::State& state) {
  ParticleFilter filter;
  filter.set_map(office_map());
  const Corridor& run = corridor();
  double calls = 0.0;
  double longest_call_s = 0.0;
  double first_s = 0.0;
  double last_s = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    filter.initialize_global(run.poses[0]);
    state.ResumeTiming();
    const msgs::LaserScan* scan = &run.scans[1];
    calls = 0.0;
    for (FilterUpdate outcome = FilterUpdate::kWeighing; outcome == FilterUpdate::kWeighing;
         scan = nullptr) {
      const auto started = std::chrono::steady_clock::now();
      outcome = filter.update(run.poses[1], scan);
      const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      if (calls == 0.0) first_s += took;
      if (outcome != FilterUpdate::kWeighing) last_s += took;
      longest_call_s = std::max(longest_call_s, took);
      calls += 1.0;
    }
  }
  state.counters["calls"] = calls;
  state.counters["longest_call_ms"] = 1e3 * longest_call_s;
  state.counters["first_call_ms"] = 1e3 * first_s / static_cast<double>(state.iterations());
  state.counters["last_call_ms"] = 1e3 * last_s / static_cast<double>(state.iterations());
}
BENCHMARK(BM_ParticleFilterGlobalUpdate)->Unit(benchmark::kMillisecond);

std::vector<WeightedPose> cloud(std::size_t count, const Pose2D& centre) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 0.1);
  std::vector<WeightedPose> out;
  for (std::size_t i = 0; i < count; ++i) {
    out.push_back({{centre.x + n(rng), centre.y + n(rng), centre.theta + 0.5 * n(rng)},
                   1.0 / static_cast<double>(count)});
  }
  return out;
}

// The weighing alone, with the beams that return nothing walked as free rays (the default) and
// without (AMCL's model): what the free rays cost.
void weigh_2000x60(benchmark::State& state, bool no_return_beams) {
  BeamLikelihoodOptions options;
  options.no_return_beams = no_return_beams;
  const BeamLikelihood model(office_map().field, options);
  const PreparedScan scan = model.prepare(corridor().scans[10]);
  const auto particles = cloud(2000, corridor().poses[10]);
  for (auto _ : state) {
    double total = 0.0;
    for (const WeightedPose& p : particles) total += model.log_likelihood(scan, p.pose);
    benchmark::DoNotOptimize(total);
  }
  state.counters["beams"] = static_cast<double>(scan.endpoints_in_base.size());
  state.counters["free_rays"] = static_cast<double>(scan.free_ray_ends_in_base.size());
}
void BM_ParticleFilterWeigh2000x60(benchmark::State& state) { weigh_2000x60(state, true); }
BENCHMARK(BM_ParticleFilterWeigh2000x60)->Unit(benchmark::kMicrosecond);
void BM_ParticleFilterWeigh2000x60ReturnsOnly(benchmark::State& state) {
  weigh_2000x60(state, false);
}
BENCHMARK(BM_ParticleFilterWeigh2000x60ReturnsOnly)->Unit(benchmark::kMicrosecond);

void BM_ParticleFilterKldResample2000(benchmark::State& state) {
  const KldSampler sampler;
  const auto particles = cloud(2000, corridor().poses[10]);
  std::mt19937_64 rng(1);
  for (auto _ : state) benchmark::DoNotOptimize(sampler.resample(particles, 0.0, {}, rng));
}
BENCHMARK(BM_ParticleFilterKldResample2000)->Unit(benchmark::kMicrosecond);

void BM_ParticleFilterCluster2000(benchmark::State& state) {
  const auto particles = cloud(2000, corridor().poses[10]);
  for (auto _ : state) benchmark::DoNotOptimize(cluster_particles(particles, {}));
}
BENCHMARK(BM_ParticleFilterCluster2000)->Unit(benchmark::kMicrosecond);

// The distance transform and free-cell list of a new map (the office, 400 x 300 cells).
void BM_ParticleFilterPrepareOfficeMap(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(prepare_particle_filter_map(office().floor));
}
BENCHMARK(BM_ParticleFilterPrepareOfficeMap)->Unit(benchmark::kMillisecond);

// The same for a 100 x 100 m floor at 5 cm (2000 x 2000 cells).
void BM_ParticleFilterPrepare2000Map(benchmark::State& state) {
  mapping::OccupancyGrid grid(2000, 2000, 0.05, {}, mapping::OccupancyGrid::kFree);
  for (int y = 0; y < 2000; y += 100) {
    for (int x = 0; x < 2000; ++x) grid.set({x, y}, mapping::OccupancyGrid::kOccupied);
  }
  for (auto _ : state) benchmark::DoNotOptimize(prepare_particle_filter_map(grid));
}
BENCHMARK(BM_ParticleFilterPrepare2000Map)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mobot::estimation
