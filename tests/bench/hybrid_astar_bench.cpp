// Hybrid A* (the tricycles' car-like global planner) on the yard world (40 x 30 m at 0.05 m,
// inflated as deploy/config/tricycle_t1.yaml does: 0.8 m inscribed, costs over 1.5 m beyond).
// Target: every plan, including a goal the body cannot reach (bounded by max_expansions), well
// under a second; the time includes the per-plan Dijkstra of the grid heuristic, which is what a
// plan whose first analytic shot succeeds costs.
//   cmake --build build --target mobot_bench && ./build/tests/bench/mobot_bench
//   --benchmark_filter=HybridAStar
#include <benchmark/benchmark.h>

#include <numbers>

#include "core/geometry/pose2d.h"
#include "core/planning/hybrid_astar_planner.h"
#include "core/planning/planning_grid.h"
#include "core/planning/planning_grid_builder.h"
#include "drivers/sim/world.h"

namespace mobot::planning {
namespace {

using geometry::Pose2D;

const PlanningGrid& yard() {
  static const PlanningGrid grid = [] {
    const sim::World world = sim::load_world(sim::resolve_world(MOBOT_DEFAULT_WORLDS_DIR, "yard"));
    PlanningGridOptions options;
    options.inscribed_radius_m = 0.8;
    options.inflation_margin_m = 1.5;
    options.cost_scaling_per_m = 3.0;
    return PlanningGridBuilder(options).build(world.floor);
  }();
  return grid;
}

void BM_HybridAStar(benchmark::State& state, Pose2D start, Pose2D goal, HybridAStarOptions options,
                    bool expect_path) {
  const PlanningGrid& grid = yard();
  HybridAStarPlanner planner(options);
  PlanResult result;
  for (auto _ : state) {
    result = planner.plan(grid, start, goal);
    benchmark::DoNotOptimize(result.length_m);
  }
  if (result.ok() != expect_path) {
    state.SkipWithError(result.ok() ? "found a path" : "no path");
    return;
  }
  state.counters["expanded"] = static_cast<double>(result.expanded_cells);
  state.counters["path_m"] = result.length_m;
}

HybridAStarOptions with_state_cell(double state_cell_m) {
  HybridAStarOptions options;
  options.state_cell_m = state_cell_m;
  return options;
}

// From the yard's start pose (5, 15) heading east:
// to the far corner past the north-west shed and the pallet stack,
BENCHMARK_CAPTURE(BM_HybridAStar, YardAcross, Pose2D{5.0, 15.0, 0.0}, Pose2D{35.0, 25.0, 0.0},
                  HybridAStarOptions{}, true)
    ->Unit(benchmark::kMillisecond);
// to a point 2 m behind it (a U-turn: the first analytic shot succeeds, so this is the fixed
// cost of a plan, mostly the heuristic's Dijkstra),
BENCHMARK_CAPTURE(BM_HybridAStar, YardBehind, Pose2D{5.0, 15.0, 0.0}, Pose2D{3.0, 15.0, 0.0},
                  HybridAStarOptions{}, true)
    ->Unit(benchmark::kMillisecond);
// into the gap between the container and the south-east shed,
BENCHMARK_CAPTURE(BM_HybridAStar, YardGap, Pose2D{5.0, 15.0, 0.0}, Pose2D{22.0, 12.0, 0.0},
                  HybridAStarOptions{}, true)
    ->Unit(benchmark::kMillisecond);
// from the south-west to the east fence past the container, at three state cell sizes,
BENCHMARK_CAPTURE(BM_HybridAStar, YardEastCell005, Pose2D{5.0, 5.0, 0.0}, Pose2D{36.0, 15.0, 0.0},
                  with_state_cell(0.05), true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_HybridAStar, YardEastCell010, Pose2D{5.0, 5.0, 0.0}, Pose2D{36.0, 15.0, 0.0},
                  with_state_cell(0.1), true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_HybridAStar, YardEastCell020, Pose2D{5.0, 5.0, 0.0}, Pose2D{36.0, 15.0, 0.0},
                  with_state_cell(0.2), true)
    ->Unit(benchmark::kMillisecond);
// from the north-east heading west back to the south-west corner,
BENCHMARK_CAPTURE(BM_HybridAStar, YardDiagonalBack, Pose2D{35.0, 25.0, std::numbers::pi},
                  Pose2D{5.0, 5.0, 0.0}, HybridAStarOptions{}, true)
    ->Unit(benchmark::kMillisecond);

// The worst case: a goal the body fits at but cannot reach, in the south-west corner facing out
// of it with the heading held exactly (a forward-only car would have to back in). The search runs
// to max_expansions and answers no_path.
HybridAStarOptions heading_held() {
  HybridAStarOptions options;
  options.goal_heading_tolerance_rad = 0.0;
  return options;
}
BENCHMARK_CAPTURE(BM_HybridAStar, YardUnreachable, Pose2D{5.0, 15.0, 0.0},
                  Pose2D{1.9, 1.9, std::numbers::pi / 4}, heading_held(), false)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mobot::planning
