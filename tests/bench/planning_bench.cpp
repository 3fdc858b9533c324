// Planning and control benchmarks. Targets: A* corner to corner on a 1000 x 1000 maze < 50 ms;
// one controller compute (Lyapunov, potential field) a few microseconds. The Voronoi planner is
// measured cold (a changed grid: roadmap + plan) and warm (roadmap cached, plan only).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <opencv2/core.hpp>
#include <random>
#include <utility>
#include <vector>

#include "core/control/lyapunov_controller.h"
#include "core/control/navigation_supervisor.h"
#include "core/control/potential_field_avoider.h"
#include "core/control/waypoint_follower.h"
#include "core/mapping/occupancy_grid.h"
#include "core/planning/astar_planner.h"
#include "core/planning/path.h"
#include "core/planning/path_smoother.h"
#include "core/planning/planning_grid.h"
#include "core/planning/planning_grid_builder.h"
#include "core/planning/voronoi_planner.h"
#include "core/planning/voronoi_roadmap.h"

namespace {

using mobot::mapping::OccupancyGrid;
using mobot::planning::PlanningGrid;

// A perfect maze by the recursive backtracker (iterative, seeded, with its own Fisher-Yates so the
// maze is the same with every standard library): maze cells of corridor_cells free cells separated
// by wall_cells walls, drawn into a side x side occupancy grid with a wall border.
OccupancyGrid make_maze(int side, int corridor_cells, int wall_cells, double resolution_m,
                        std::uint32_t seed) {
  OccupancyGrid grid(side, side, resolution_m, {}, OccupancyGrid::kOccupied);
  const int pitch = corridor_cells + wall_cells;
  const int cells = (side - wall_cells) / pitch;
  const auto carve = [&](int x0, int y0, int w, int h) {
    for (int y = y0; y < y0 + h; ++y) {
      for (int x = x0; x < x0 + w; ++x) grid.set({x, y}, OccupancyGrid::kFree);
    }
  };
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> visited(static_cast<std::size_t>(cells * cells), 0);
  std::vector<std::pair<int, int>> stack{{0, 0}};
  visited[0] = 1;
  carve(wall_cells, wall_cells, corridor_cells, corridor_cells);
  constexpr int kDx[4] = {1, -1, 0, 0};
  constexpr int kDy[4] = {0, 0, 1, -1};
  while (!stack.empty()) {
    const auto [cx, cy] = stack.back();
    int order[4] = {0, 1, 2, 3};
    for (int i = 3; i > 0; --i) std::swap(order[i], order[rng() % static_cast<unsigned>(i + 1)]);
    bool moved = false;
    for (const int d : order) {
      const int nx = cx + kDx[d];
      const int ny = cy + kDy[d];
      if (nx < 0 || ny < 0 || nx >= cells || ny >= cells) continue;
      const auto index = static_cast<std::size_t>(ny * cells + nx);
      if (visited[index] != 0) continue;
      visited[index] = 1;
      // Open the wall between the two maze cells, then the new cell.
      const int x0 = wall_cells + std::min(cx, nx) * pitch;
      const int y0 = wall_cells + std::min(cy, ny) * pitch;
      carve(x0, y0, kDx[d] != 0 ? pitch + corridor_cells : corridor_cells,
            kDy[d] != 0 ? pitch + corridor_cells : corridor_cells);
      stack.emplace_back(nx, ny);
      moved = true;
      break;
    }
    if (!moved) stack.pop_back();
  }
  return grid;
}

// The raw maze as a planning grid (no inflation): free 0, walls lethal.
PlanningGrid raw_planning_grid(const OccupancyGrid& maze) {
  PlanningGrid grid(maze.width(), maze.height(), maze.resolution_m(), maze.origin());
  for (std::size_t i = 0; i < maze.cells().size(); ++i) {
    grid.mutable_costs()[i] =
        maze.cells()[i] == OccupancyGrid::kFree ? PlanningGrid::kFree : PlanningGrid::kLethal;
  }
  return grid;
}

mobot::geometry::Pose2D centre_of(const PlanningGrid& grid, int x, int y) {
  const auto p = grid.cell_center({x, y});
  return {p.x, p.y, 0.0};
}

void run_astar(benchmark::State& state, const PlanningGrid& grid, mobot::geometry::Pose2D start,
               mobot::geometry::Pose2D goal) {
  mobot::planning::AStarPlanner planner;
  mobot::planning::PlanResult result;
  for (auto _ : state) {
    result = planner.plan(grid, start, goal);
    benchmark::DoNotOptimize(result.cost);
  }
  if (!result.ok()) state.SkipWithError("no path");
  state.counters["expanded"] = static_cast<double>(result.expanded_cells);
  state.counters["path_m"] = result.length_m;
}

// 1000 x 1000, corridors 3 cells wide, walls 1 cell: about 1e6 cells, most of them reachable.
void BM_AStarMaze1000Narrow(benchmark::State& state) {
  static const PlanningGrid grid = raw_planning_grid(make_maze(1000, 3, 1, 0.05, 1));
  // Maze cells span [1 + 4 k, 1 + 4 k + 3): the last one (k = 248) is centred on cell 994.
  run_astar(state, grid, centre_of(grid, 2, 2), centre_of(grid, 994, 994));
}
BENCHMARK(BM_AStarMaze1000Narrow)->Unit(benchmark::kMillisecond);

// 1000 x 1000 at 0.05 m with 1.2 m corridors, inflated for R1 (what the robot really plans on).
void BM_AStarMaze1000Inflated(benchmark::State& state) {
  static const PlanningGrid grid =
      mobot::planning::PlanningGridBuilder().build(make_maze(1000, 24, 2, 0.05, 2));
  // Maze cells span [2 + 26 k, 2 + 26 k + 24): the first and last (k = 37) centres.
  run_astar(state, grid, centre_of(grid, 14, 14), centre_of(grid, 976, 976));
}
BENCHMARK(BM_AStarMaze1000Inflated)->Unit(benchmark::kMillisecond);

void BM_AStarOpen1000(benchmark::State& state) {
  static const PlanningGrid grid(1000, 1000, 0.05, {});
  run_astar(state, grid, centre_of(grid, 0, 0), centre_of(grid, 999, 999));
}
BENCHMARK(BM_AStarOpen1000)->Unit(benchmark::kMillisecond);

// Open ground off the diagonal: a wide band of cells shares the optimal f, so most pushes land in
// the open list's current bucket (its slow path); a guard against regressions there.
void BM_AStarOpen1000Skewed(benchmark::State& state) {
  static const PlanningGrid grid(1000, 1000, 0.05, {});
  run_astar(state, grid, centre_of(grid, 0, 0), centre_of(grid, 999, 700));
}
BENCHMARK(BM_AStarOpen1000Skewed)->Unit(benchmark::kMillisecond);

// A 20 x 20 m office at 0.05 m: a 2 m corridor across the middle, five 4 m rooms on each side,
// each with a 0.9 m door onto the corridor and a desk against its back wall, inside 0.1 m walls.
OccupancyGrid make_office() {
  constexpr int kSide = 400;
  OccupancyGrid grid(kSide, kSide, 0.05, {}, OccupancyGrid::kFree);
  const auto wall = [&](int x0, int y0, int x1, int y1) {
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) grid.set({x, y}, OccupancyGrid::kOccupied);
    }
  };
  const auto opening = [&](int x0, int y0, int x1, int y1) {
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) grid.set({x, y}, OccupancyGrid::kFree);
    }
  };
  wall(0, 0, kSide - 1, 1);
  wall(0, kSide - 2, kSide - 1, kSide - 1);
  wall(0, 0, 1, kSide - 1);
  wall(kSide - 2, 0, kSide - 1, kSide - 1);
  wall(0, 178, kSide - 1, 179);  // the corridor, y 180..219
  wall(0, 220, kSide - 1, 221);
  for (int room = 0; room < 5; ++room) {
    const int x0 = room * 80;
    if (room > 0) {
      wall(x0, 0, x0 + 1, 177);
      wall(x0, 222, x0 + 1, kSide - 1);
    }
    const int door = x0 + 20 + 8 * room;  // the doors are not all in line
    opening(door, 178, door + 17, 179);
    opening(door + 10, 220, door + 27, 221);
    wall(x0 + 15, 12, x0 + 45, 25);  // desks
    wall(x0 + 30, kSide - 26, x0 + 60, kSide - 13);
  }
  return grid;
}

// cold: every plan is on a changed grid (two grids in turn that differ in one wall cell, lethal in
// one and unknown in the other: the same roadmap, but the cache cannot know), so each plan builds
// the roadmap, as after a map update; the planner and its buffers are reused, as by the server.
// warm: the same grid every time, the roadmap cached.
void run_voronoi(benchmark::State& state, const PlanningGrid& grid, mobot::geometry::Pose2D start,
                 mobot::geometry::Pose2D goal, bool cold) {
  PlanningGrid other = grid;
  if (other.cost({0, 0}) != PlanningGrid::kLethal) {
    state.SkipWithError("cell (0, 0) is not a wall");
    return;
  }
  other.set_cost({0, 0}, PlanningGrid::kUnknown);
  mobot::planning::VoronoiPlanner planner;
  mobot::planning::PlanResult result;
  bool flip = false;
  const std::size_t builds_before = planner.roadmap_builds();
  for (auto _ : state) {
    flip = cold && !flip;
    result = planner.plan(flip ? other : grid, start, goal);
    benchmark::DoNotOptimize(result.cost);
  }
  if (!result.ok()) state.SkipWithError("no path");
  state.counters["builds_per_plan"] =
      static_cast<double>(planner.roadmap_builds() - builds_before) /
      static_cast<double>(state.iterations());
  state.counters["expanded"] = static_cast<double>(result.expanded_cells);
  state.counters["path_m"] = result.length_m;
  state.counters["cells"] = static_cast<double>(result.cells.size());
  state.counters["waypoints"] = static_cast<double>(result.points_in_map.size());
  state.counters["roadmap_cells"] = static_cast<double>(planner.roadmap_for(grid).size());
}

void run_voronoi_roadmap(benchmark::State& state, const PlanningGrid& grid) {
  std::size_t cells = 0;
  for (auto _ : state) {
    const mobot::planning::VoronoiRoadmap roadmap(grid);
    cells = roadmap.size();
    benchmark::DoNotOptimize(roadmap.mask().data());
  }
  state.counters["roadmap_cells"] = static_cast<double>(cells);
}

const PlanningGrid& office_grid() {
  static const PlanningGrid grid = mobot::planning::PlanningGridBuilder().build(make_office());
  return grid;
}

// The inflated maze of BM_AStarMaze1000Inflated.
const PlanningGrid& inflated_maze_grid() {
  static const PlanningGrid grid =
      mobot::planning::PlanningGridBuilder().build(make_maze(1000, 24, 2, 0.05, 2));
  return grid;
}

// From the lower-left room to the upper-right one, through two doors and along the corridor.
constexpr mobot::geometry::Pose2D kOfficeStart{2.0, 5.0, 0.0};
constexpr mobot::geometry::Pose2D kOfficeGoal{18.0, 15.0, 0.0};

void BM_VoronoiRoadmapOffice400(benchmark::State& state) {
  run_voronoi_roadmap(state, office_grid());
}
BENCHMARK(BM_VoronoiRoadmapOffice400)->Unit(benchmark::kMillisecond);

void BM_VoronoiColdOffice400(benchmark::State& state) {
  run_voronoi(state, office_grid(), kOfficeStart, kOfficeGoal, true);
}
BENCHMARK(BM_VoronoiColdOffice400)->Unit(benchmark::kMillisecond);

void BM_VoronoiWarmOffice400(benchmark::State& state) {
  run_voronoi(state, office_grid(), kOfficeStart, kOfficeGoal, false);
}
BENCHMARK(BM_VoronoiWarmOffice400)->Unit(benchmark::kMillisecond);

void BM_AStarOffice400(benchmark::State& state) {
  run_astar(state, office_grid(), kOfficeStart, kOfficeGoal);
}
BENCHMARK(BM_AStarOffice400)->Unit(benchmark::kMillisecond);

void BM_VoronoiRoadmapMaze1000Inflated(benchmark::State& state) {
  run_voronoi_roadmap(state, inflated_maze_grid());
}
BENCHMARK(BM_VoronoiRoadmapMaze1000Inflated)->Unit(benchmark::kMillisecond);

void BM_VoronoiColdMaze1000Inflated(benchmark::State& state) {
  const PlanningGrid& grid = inflated_maze_grid();
  run_voronoi(state, grid, centre_of(grid, 14, 14), centre_of(grid, 976, 976), true);
}
BENCHMARK(BM_VoronoiColdMaze1000Inflated)->Unit(benchmark::kMillisecond);

void BM_VoronoiWarmMaze1000Inflated(benchmark::State& state) {
  const PlanningGrid& grid = inflated_maze_grid();
  run_voronoi(state, grid, centre_of(grid, 14, 14), centre_of(grid, 976, 976), false);
}
BENCHMARK(BM_VoronoiWarmMaze1000Inflated)->Unit(benchmark::kMillisecond);

void BM_Inflation2000(benchmark::State& state) {
  static const OccupancyGrid maze = make_maze(2000, 24, 2, 0.05, 3);
  const mobot::planning::PlanningGridBuilder builder;
  for (auto _ : state) {
    PlanningGrid grid = builder.build(maze);
    benchmark::DoNotOptimize(grid.costs().data());
  }
}
BENCHMARK(BM_Inflation2000)->Unit(benchmark::kMillisecond)->UseRealTime();

// cv::distanceTransform runs on OpenCV's thread pool; this is the cost on one thread (what the
// planning worker pays if the server calls cv::setNumThreads(1)).
void BM_Inflation2000OneThread(benchmark::State& state) {
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  BM_Inflation2000(state);
  cv::setNumThreads(threads);
}
BENCHMARK(BM_Inflation2000OneThread)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PathSmoothingInflatedMaze(benchmark::State& state) {
  static const PlanningGrid grid =
      mobot::planning::PlanningGridBuilder().build(make_maze(1000, 24, 2, 0.05, 2));
  mobot::planning::AStarPlanner planner;
  const auto plan = planner.plan(grid, centre_of(grid, 14, 14), centre_of(grid, 976, 976));
  const mobot::planning::PathSmoother smoother;
  std::size_t points = 0;
  for (auto _ : state) {
    const auto smooth = smoother.smooth(grid, plan.points_in_map);
    points = smooth.size();
    benchmark::DoNotOptimize(smooth.data());
  }
  state.counters["in_points"] = static_cast<double>(plan.points_in_map.size());
  state.counters["out_points"] = static_cast<double>(points);
}
BENCHMARK(BM_PathSmoothingInflatedMaze)->Unit(benchmark::kMillisecond);

void BM_LyapunovCompute(benchmark::State& state) {
  mobot::control::LyapunovController controller;
  mobot::geometry::Pose2D pose{-2.0, 3.5, -1.0};
  for (auto _ : state) {
    pose.x += 1e-9;  // defeat hoisting
    benchmark::DoNotOptimize(controller.compute(pose, {0.0, 0.0, 0.0}));
  }
}
BENCHMARK(BM_LyapunovCompute);

void BM_WaypointFollowerCompute(benchmark::State& state) {
  std::vector<mobot::geometry::Point2D> points;
  for (int i = 0; i <= 200; ++i) points.push_back({0.3 * i, 0.1 * (i % 2)});
  mobot::control::WaypointFollower follower;
  follower.set_path(mobot::planning::Path(points), 0.0);
  mobot::geometry::Pose2D pose{5.0, 0.05, 0.0};
  for (auto _ : state) {
    benchmark::DoNotOptimize(follower.compute(pose, {0.5, 0.0}, 0.0));
  }
}
BENCHMARK(BM_WaypointFollowerCompute);

std::vector<mobot::msgs::RangeReading> ring_of_eight() {
  std::vector<mobot::msgs::RangeReading> ring;
  for (int i = 0; i < 8; ++i) {
    mobot::msgs::RangeReading r;
    const double bearing = -std::numbers::pi / 2.0 + i * std::numbers::pi / 7.0;
    r.sensor_in_base = {0.3 * std::cos(bearing), 0.3 * std::sin(bearing), bearing};
    r.cone_rad = 0.39;
    r.range_min_m = 0.03;
    r.range_max_m = 4.0;
    r.range_m = 0.4 + 0.1 * i;
    ring.push_back(r);
  }
  return ring;
}

void BM_PotentialFieldCompute(benchmark::State& state) {
  mobot::control::PotentialFieldAvoider avoider;
  const auto ring = ring_of_eight();
  for (auto _ : state) {
    benchmark::DoNotOptimize(avoider.compute({0.0, 0.0, 0.1}, {3.0, 0.5}, ring));
    benchmark::DoNotOptimize(avoider.is_active(ring));
  }
}
BENCHMARK(BM_PotentialFieldCompute);

void BM_NavigationSupervisorUpdate(benchmark::State& state) {
  std::vector<mobot::geometry::Point2D> points;
  for (int i = 0; i <= 200; ++i) points.push_back({0.3 * i, 0.0});
  mobot::control::NavigationSupervisor supervisor({}, {});
  supervisor.set_path(mobot::planning::Path(points), 0.0);
  const auto ring = ring_of_eight();
  double t = 0.0;
  for (auto _ : state) {
    t += 0.02;
    benchmark::DoNotOptimize(supervisor.update(t, {5.0, 0.2, 0.0}, ring));
  }
}
BENCHMARK(BM_NavigationSupervisorUpdate);

}  // namespace
