// Costmap cost (docs/algorithms.md P3): the rolling 3 x 3 m local window updated from one 720-beam
// 360 degree scan (target < 1 ms), and a global costmap rebuild of a 2000 x 2000 map with
// inflation (target < 40 ms).
//   cmake --build build --target mobot_bench && ./build/tests/bench/mobot_bench
//   --benchmark_filter=Costmap

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "core/costmap/inflation_layer.h"
#include "core/costmap/layered_costmap.h"
#include "core/costmap/obstacle_layer.h"
#include "core/costmap/static_layer.h"
#include "core/mapping/occupancy_grid.h"
#include "core/msgs/laser_scan.h"

namespace mobot::costmap {
namespace {

using mapping::OccupancyGrid;

void fill(OccupancyGrid& grid, int min_x, int min_y, int max_x, int max_y, std::uint8_t value) {
  for (int y = std::max(min_y, 0); y <= std::min(max_y, grid.height() - 1); ++y) {
    for (int x = std::max(min_x, 0); x <= std::min(max_x, grid.width() - 1); ++x) {
      grid.set({x, y}, value);
    }
  }
}

// A 100 x 100 m floor at 0.05 m: bands of rooms 6-12 m deep between 2 m corridors, rooms 4-10 m
// wide with 1.2 m doors, furniture in some rooms, outer walls (as raycast_bench's office).
OccupancyGrid synthetic_office() {
  constexpr int kSize = 2000;
  constexpr int kWall = 3;
  OccupancyGrid grid(kSize, kSize, 0.05, {}, OccupancyGrid::kFree);
  std::mt19937_64 rng(7);
  const auto uniform = [&rng](int lo, int hi) {
    return std::uniform_int_distribution<int>(lo, hi)(rng);
  };
  int y = 0;
  while (y < kSize - 120) {
    const int top = std::min(y + uniform(120, 240), kSize - 1);
    fill(grid, 0, y, kSize - 1, y + kWall - 1, OccupancyGrid::kOccupied);
    fill(grid, 0, top - kWall + 1, kSize - 1, top, OccupancyGrid::kOccupied);
    int x = 0;
    while (x < kSize - 80) {
      const int width = uniform(80, 200);
      fill(grid, x, y, x + kWall - 1, top, OccupancyGrid::kOccupied);
      const int door_y = uniform(y + 10, top - 40);
      fill(grid, x, door_y, x + kWall - 1, door_y + 24, OccupancyGrid::kFree);
      const int door_x = uniform(x + 10, x + width - 40);
      fill(grid, door_x, top - kWall + 1, door_x + 24, top, OccupancyGrid::kFree);
      if (uniform(0, 2) == 0) {
        const int fx = uniform(x + 20, x + width - 50);
        const int fy = uniform(y + 20, top - 50);
        fill(grid, fx, fy, fx + uniform(10, 30), fy + uniform(10, 30), OccupancyGrid::kOccupied);
      }
      x += width;
    }
    y = top + 40;
  }
  fill(grid, 0, 0, kSize - 1, kWall - 1, OccupancyGrid::kOccupied);
  fill(grid, 0, kSize - kWall, kSize - 1, kSize - 1, OccupancyGrid::kOccupied);
  fill(grid, 0, 0, kWall - 1, kSize - 1, OccupancyGrid::kOccupied);
  fill(grid, kSize - kWall, 0, kSize - 1, kSize - 1, OccupancyGrid::kOccupied);
  return grid;
}

// The dense case: 2-cell walls every 26 cells both ways (1.2 m rooms), every wall with a door.
// Nearly every cell is within the inflation radius of a wall.
OccupancyGrid dense_rooms() {
  constexpr int kSize = 2000;
  OccupancyGrid grid(kSize, kSize, 0.05, {}, OccupancyGrid::kFree);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const bool wall = (x % 26) < 2 || (y % 26) < 2;
      const bool door =
          (x % 26) >= 10 && (x % 26) < 16 ? (y % 26) < 2 : (y % 26) >= 10 && (y % 26) < 16;
      if (wall && !door) grid.set({x, y}, OccupancyGrid::kOccupied);
    }
  }
  return grid;
}

const OccupancyGrid& office() {
  static const OccupancyGrid map = synthetic_office();
  return map;
}

// One 720-beam 360 degree scan from `pose` by marching the map in 1 cm steps (setup only).
msgs::LaserScan scan_from(const OccupancyGrid& map, const geometry::Pose2D& pose, int beams) {
  msgs::LaserScan scan;
  scan.angle_min_rad = static_cast<float>(-std::numbers::pi);
  scan.angle_increment_rad = static_cast<float>(2.0 * std::numbers::pi / beams);
  scan.range_min_m = 0.05F;
  scan.range_max_m = 12.0F;
  for (int i = 0; i < beams; ++i) {
    const double angle = pose.theta + scan.angle_min_rad + i * scan.angle_increment_rad;
    double r = 0.05;
    for (; r < scan.range_max_m; r += 0.01) {
      const auto cell = map.cell_at({pose.x + r * std::cos(angle), pose.y + r * std::sin(angle)});
      if (!cell || map.is_occupied(*cell)) break;
    }
    scan.ranges_m.push_back(static_cast<float>(r));
  }
  return scan;
}

// Poses along a corridor of the office, 3 cm apart (0.3 m/s at the laser's 10 Hz).
std::vector<geometry::Pose2D> corridor_poses(const OccupancyGrid& map, int count) {
  // Find a free row: the first corridor band above y = 10 m.
  double y = 10.0;
  for (; y < 90.0; y += 0.05) {
    bool clear = true;
    for (double x = 10.0; x < 10.0 + 0.03 * count && clear; x += 0.05) {
      for (double dy = -1.0; dy <= 1.0 && clear; dy += 0.05) {
        const auto cell = map.cell_at({x, y + dy});
        clear = cell && !map.is_occupied(*cell);
      }
    }
    if (clear) break;
  }
  std::vector<geometry::Pose2D> poses;
  for (int i = 0; i < count; ++i) poses.push_back({10.0 + 0.03 * i, y, 0.0});
  return poses;
}

void BM_CostmapRollingWindowUpdateFrom720BeamScan(benchmark::State& state) {
  const OccupancyGrid& map = office();
  const std::vector<geometry::Pose2D> poses = corridor_poses(map, 200);
  std::vector<msgs::LaserScan> scans;
  for (const auto& pose : poses) scans.push_back(scan_from(map, pose, 720));

  LayeredCostmapOptions options;
  options.rolling = true;
  LayeredCostmap costmap(options);
  costmap.add(std::make_unique<StaticLayer>()).set_map(map);
  ObstacleLayer& laser = costmap.add(std::make_unique<ObstacleLayer>());
  costmap.add(std::make_unique<InflationLayer>());
  costmap.update(poses.front());
  std::size_t i = 0;
  std::size_t cells = 0;
  for (auto _ : state) {
    const std::size_t k = i++ % poses.size();
    laser.add_scan(scans[k], poses[k]);
    cells += costmap.update(poses[k]).cell_count();
    benchmark::DoNotOptimize(costmap.master().costs().data());
  }
  state.counters["cells_per_update"] =
      benchmark::Counter(static_cast<double>(cells), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_CostmapRollingWindowUpdateFrom720BeamScan)->Unit(benchmark::kMicrosecond);

void run_global_rebuild(benchmark::State& state, const OccupancyGrid& map,
                        const InflationLayerOptions& inflation) {
  LayeredCostmap costmap;
  costmap.add(std::make_unique<StaticLayer>()).set_map(map);
  costmap.add(std::make_unique<InflationLayer>(inflation));
  costmap.resize_to(map);
  costmap.update({});
  for (auto _ : state) {
    costmap.rebuild();
    benchmark::DoNotOptimize(costmap.master().costs().data());
  }
}

// The Dashgo's inflation (inscribed 0.2 m, radius 0.25 m).
void BM_CostmapGlobalRebuild2000(benchmark::State& state) {
  run_global_rebuild(state, office(), InflationLayerOptions{});
}
BENCHMARK(BM_CostmapGlobalRebuild2000)->Unit(benchmark::kMillisecond);

// R1's planning inflation (inscribed 0.42 m as in the config, band 0.25 m, unknown inflated).
InflationLayerOptions r1_inflation() {
  InflationLayerOptions options;
  options.inscribed_radius_m = 0.42;
  options.inflation_radius_m = 0.67;
  options.inflate_unknown = true;
  return options;
}

void BM_CostmapGlobalRebuild2000R1(benchmark::State& state) {
  run_global_rebuild(state, office(), r1_inflation());
}
BENCHMARK(BM_CostmapGlobalRebuild2000R1)->Unit(benchmark::kMillisecond);

void BM_CostmapGlobalRebuild2000Dense(benchmark::State& state) {
  static const OccupancyGrid dense = dense_rooms();
  run_global_rebuild(state, dense, r1_inflation());
}
BENCHMARK(BM_CostmapGlobalRebuild2000Dense)->Unit(benchmark::kMillisecond);

// A new map: conversion of the occupancy grid plus the rebuild.
void BM_CostmapGlobalSetMapAndRebuild2000(benchmark::State& state) {
  const OccupancyGrid& map = office();
  LayeredCostmap costmap;
  StaticLayer& static_layer = costmap.add(std::make_unique<StaticLayer>());
  costmap.add(std::make_unique<InflationLayer>());
  for (auto _ : state) {
    static_layer.set_map(map);
    costmap.resize_to(map);
    costmap.update({});
    benchmark::DoNotOptimize(costmap.master().costs().data());
  }
}
BENCHMARK(BM_CostmapGlobalSetMapAndRebuild2000)->Unit(benchmark::kMillisecond);

// The global costmap's laser layer (8 m marking): one scan, only its neighbourhood recomputed.
void BM_CostmapGlobalUpdateFrom720BeamScan(benchmark::State& state) {
  const OccupancyGrid& map = office();
  const std::vector<geometry::Pose2D> poses = corridor_poses(map, 50);
  std::vector<msgs::LaserScan> scans;
  for (const auto& pose : poses) scans.push_back(scan_from(map, pose, 720));
  LayeredCostmap costmap;
  costmap.add(std::make_unique<StaticLayer>()).set_map(map);
  ObstacleLayerOptions laser_options;
  laser_options.obstacle_range_m = 8.0;
  laser_options.raytrace_range_m = 8.5;
  ObstacleLayer& laser = costmap.add(std::make_unique<ObstacleLayer>(laser_options));
  costmap.add(std::make_unique<InflationLayer>());
  costmap.resize_to(map);
  costmap.update({});
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++ % poses.size();
    laser.add_scan(scans[k], poses[k]);
    costmap.update(poses[k]);
    benchmark::DoNotOptimize(costmap.master().costs().data());
  }
}
BENCHMARK(BM_CostmapGlobalUpdateFrom720BeamScan)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mobot::costmap
