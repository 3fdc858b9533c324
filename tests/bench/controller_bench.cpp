// Local planners (docs/algorithms.md C5): one DWA and one VFH compute() on the 3 x 3 m local
// costmap at 0.05 m with an obstacle ahead, cruising.
//   cmake --build build --target mobot_bench && ./build/tests/bench/mobot_bench
//   --benchmark_filter=Tracker

#include <benchmark/benchmark.h>

#include <memory>

#include "core/control/dwa_tracker.h"
#include "core/control/vfh_tracker.h"
#include "core/costmap/inflation_layer.h"
#include "core/costmap/layered_costmap.h"
#include "core/costmap/static_layer.h"
#include "core/mapping/occupancy_grid.h"

namespace mobot::control {
namespace {

// The rolling window around (0, 0) over a free map with a 0.3 m box 1 m ahead, beside the path.
std::shared_ptr<const planning::PlanningGrid> local_window() {
  mapping::OccupancyGrid map(200, 200, 0.05, {-5.0, -5.0, 0.0}, mapping::OccupancyGrid::kFree);
  for (int y = 104; y < 110; ++y) {
    for (int x = 120; x < 126; ++x) map.set({x, y}, mapping::OccupancyGrid::kOccupied);
  }
  costmap::LayeredCostmapOptions options;
  options.rolling = true;
  options.lattice_origin_m = {-5.0, -5.0};
  costmap::LayeredCostmap costmap(options);
  costmap.add(std::make_unique<costmap::StaticLayer>()).set_map(map);
  costmap.add(std::make_unique<costmap::InflationLayer>());
  costmap.update({0.0, 0.0, 0.0});
  return costmap.snapshot();
}

template <class Tracker>
void run(benchmark::State& state) {
  Tracker tracker;
  tracker.set_path(planning::Path({{0.0, 0.0}, {4.0, 0.0}}), 0.0);
  tracker.set_local_costmap(local_window());
  const geometry::Pose2D pose{0.0, 0.0, 0.0};
  const msgs::Twist cruising{0.25, 0.0};
  double t = 0.0;
  for (auto _ : state) {
    const msgs::Twist u = tracker.compute(pose, cruising, t);
    t += 0.02;
    benchmark::DoNotOptimize(u);
  }
}

void BM_DwaTrackerCompute(benchmark::State& state) { run<DwaTracker>(state); }
BENCHMARK(BM_DwaTrackerCompute)->Unit(benchmark::kMicrosecond);

void BM_VfhTrackerCompute(benchmark::State& state) { run<VfhTracker>(state); }
BENCHMARK(BM_VfhTrackerCompute)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace mobot::control
