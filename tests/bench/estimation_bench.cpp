// Estimation core timings: EKF predict and updates (E2), scan and map line extraction.
#include <benchmark/benchmark.h>

#include <numbers>
#include <random>

#include "core/estimation/ekf_localizer.h"
#include "core/estimation/landmark_ekf.h"
#include "core/mapping/occupancy_grid.h"
#include "core/perception/line_extractor.h"
#include "core/perception/map_line_extractor.h"
#include "tests/unit/core/estimation/synthetic_world.h"

namespace {

using mobot::estimation::EkfLocalizer;
using mobot::geometry::Pose2D;
using mobot::perception::LineSegment;
namespace sim = mobot::estimation_sim;

constexpr double kPi = std::numbers::pi;

// An office-like floor: an outer room and a few pillars, 24 wall faces.
std::vector<sim::Wall> office() {
  std::vector<sim::Wall> walls = sim::rectangle_room(0.0, 0.0, 20.0, 15.0);
  for (const auto& [x, y] :
       {std::pair{5.0, 5.0}, {10.0, 4.0}, {15.0, 6.0}, {6.0, 11.0}, {14.0, 11.0}}) {
    const auto pillar = sim::rectangle_room(x, y, x + 0.6, y + 0.6);
    walls.insert(walls.end(), pillar.begin(), pillar.end());
  }
  return walls;
}

Eigen::Matrix3d moderate_covariance() { return Eigen::Vector3d(0.01, 0.01, 0.003).asDiagonal(); }

void BM_EkfPredict(benchmark::State& state) {
  EkfLocalizer ekf({}, {1.0, 2.0, 0.3}, moderate_covariance());
  for (auto _ : state) {
    ekf.predict(0.031, 0.029, 0.6);
    benchmark::DoNotOptimize(ekf.covariance());
  }
}
BENCHMARK(BM_EkfPredict);

void BM_EkfUpdateCompass(benchmark::State& state) {
  const EkfLocalizer start({}, {1.0, 2.0, 0.3}, moderate_covariance());
  for (auto _ : state) {
    EkfLocalizer ekf = start;
    benchmark::DoNotOptimize(ekf.update_compass(0.31));
  }
}
BENCHMARK(BM_EkfUpdateCompass);

// Ten observed lines (the exact view of ten map faces, with covariances) against the 24-line
// office map: matching (10 x 24 candidates, all gates) plus one stacked 20-row update.
void BM_EkfUpdateLines(benchmark::State& state) {
  const auto map = sim::wall_lines(office());
  const Pose2D truth{8.0, 7.0, 0.4};
  const Pose2D mount{0.25, 0.0, 0.0};
  std::vector<LineSegment> observed;
  for (std::size_t j = 0;
       j < map.size() && observed.size() < static_cast<std::size_t>(state.range(0)); j += 2) {
    LineSegment seen = mobot::perception::transform_line(
        mobot::geometry::inverse(mobot::geometry::compose(truth, mount)), map[j]);
    seen.var_rho_m2 = 1e-4;
    seen.var_alpha_rad2 = 1e-4;
    observed.push_back(seen);
  }
  const EkfLocalizer start({}, {8.05, 6.97, 0.41}, moderate_covariance());
  std::size_t matched = 0;
  for (auto _ : state) {
    EkfLocalizer ekf = start;
    const auto report = ekf.update_lines(observed, mount, map);
    matched = report.matches.size();
    benchmark::DoNotOptimize(ekf.pose());
  }
  state.counters["observed"] = static_cast<double>(observed.size());
  state.counters["matched"] = static_cast<double>(matched);
  state.counters["map_lines"] = static_cast<double>(map.size());
}
BENCHMARK(BM_EkfUpdateLines)->Arg(10)->Unit(benchmark::kMicrosecond);

void BM_EkfUpdateBearing(benchmark::State& state) {
  const EkfLocalizer start({}, {1.0, 2.0, 0.3}, moderate_covariance());
  for (auto _ : state) {
    EkfLocalizer ekf = start;
    benchmark::DoNotOptimize(ekf.update_bearing(0.7, {5.0, 6.0}));
  }
}
BENCHMARK(BM_EkfUpdateBearing);

void BM_LandmarkEkfStep(benchmark::State& state) {
  const mobot::estimation::LandmarkEkf start({}, {0.0, 0.0, 0.1},
                                             Eigen::Vector3d(0.1, 0.1, 0.01).asDiagonal());
  const std::vector<mobot::estimation::RangeBearingObservation> observations = {
      {{10.0, 10.0}, 14.1, 0.68}, {{-5.0, 15.0}, 15.8, 1.79}};
  for (auto _ : state) {
    auto ekf = start;
    ekf.predict(1.0, 0.1, 0.1);
    benchmark::DoNotOptimize(ekf.update(observations));
  }
}
BENCHMARK(BM_LandmarkEkfStep);

// A 361-beam, 180 deg scan (SICK LMS2xx at 0.5 deg) in the office, 1 cm range noise.
void BM_LineExtraction361(benchmark::State& state) {
  std::mt19937 rng(1);
  sim::ScanSpec spec;
  spec.range_sigma_m = 0.01;
  const auto scan = sim::simulate_scan(office(), {8.0, 7.0, 0.4}, {0.25, 0.0, 0.0}, spec, &rng);
  const mobot::perception::LineExtractor extractor;
  std::size_t lines = 0;
  for (auto _ : state) {
    const auto extracted = extractor.extract(scan);
    lines = extracted.size();
    benchmark::DoNotOptimize(extracted.data());
  }
  state.counters["lines"] = static_cast<double>(lines);
}
BENCHMARK(BM_LineExtraction361)->Unit(benchmark::kMicrosecond);

// A 400 x 300 cell map (20 x 15 m at 5 cm): walls 2 cells thick, pillars, an inner wall with a
// door, a diagonal wall; the outside unknown.
mobot::mapping::OccupancyGrid office_grid() {
  using mobot::mapping::OccupancyGrid;
  OccupancyGrid grid(400, 300, 0.05, {}, OccupancyGrid::kUnknown);
  for (int y = 10; y < 290; ++y) {
    for (int x = 10; x < 390; ++x) {
      const bool wall = x < 12 || x >= 388 || y < 12 || y >= 288;
      grid.set({x, y}, wall ? OccupancyGrid::kOccupied : OccupancyGrid::kFree);
    }
  }
  for (const auto& [x0, y0] :
       {std::pair{100, 100}, {200, 80}, {300, 120}, {120, 220}, {280, 220}}) {
    for (int y = y0; y < y0 + 12; ++y) {
      for (int x = x0; x < x0 + 12; ++x) grid.set({x, y}, OccupancyGrid::kOccupied);
    }
  }
  for (int y = 12; y < 288; ++y) {
    if (y < 140 || y > 160) grid.set({200, y}, OccupancyGrid::kOccupied);
  }
  for (int i = 0; i < 60; ++i) {
    grid.set({40 + i, 40 + i}, OccupancyGrid::kOccupied);
    grid.set({41 + i, 40 + i}, OccupancyGrid::kOccupied);
  }
  return grid;
}

void BM_MapLineExtraction400x300(benchmark::State& state) {
  const auto grid = office_grid();
  std::size_t lines = 0;
  for (auto _ : state) {
    const auto extracted = mobot::perception::extract_map_lines(grid);
    lines = extracted.size();
    benchmark::DoNotOptimize(extracted.data());
  }
  state.counters["lines"] = static_cast<double>(lines);
}
BENCHMARK(BM_MapLineExtraction400x300)->Unit(benchmark::kMillisecond);

}  // namespace
