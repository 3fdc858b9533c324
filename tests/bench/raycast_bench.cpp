// Laser simulation cost: one 361-beam scan on a 2000 x 2000 grid (target < 50 us), on the built-in
// office, and a full Simulator::step + read_laser.
//   cmake --build build --target mobot_bench && ./build/tests/bench/mobot_bench
//   --benchmark_filter=Scan

#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <vector>

#include "core/mapping/occupancy_grid.h"
#include "drivers/sim/ray_caster.h"
#include "drivers/sim/robot_profile.h"
#include "drivers/sim/simulator.h"
#include "drivers/sim/world.h"

namespace mobot::sim {
namespace {

using mapping::OccupancyGrid;

constexpr int kBeams = 361;
constexpr double kStep_rad = std::numbers::pi / 360.0;
constexpr double kRangeMax_m = 80.0;

void fill(OccupancyGrid& grid, int min_x, int min_y, int max_x, int max_y, std::uint8_t value) {
  for (int y = std::max(min_y, 0); y <= std::min(max_y, grid.height() - 1); ++y) {
    for (int x = std::max(min_x, 0); x <= std::min(max_x, grid.width() - 1); ++x) {
      grid.set({x, y}, value);
    }
  }
}

// A 100 x 100 m floor at 0.05 m: bands of rooms 6-12 m deep between 2 m corridors, rooms 4-10 m
// wide with 1.2 m doors, furniture blocks in some rooms, outer walls.
OccupancyGrid synthetic_office(std::uint64_t seed) {
  constexpr int kSize = 2000;
  constexpr int kWall = 3;  // 0.15 m
  OccupancyGrid grid(kSize, kSize, 0.05, {}, OccupancyGrid::kFree);
  std::mt19937_64 rng(seed);
  const auto uniform = [&rng](int lo, int hi) {
    return std::uniform_int_distribution<int>(lo, hi)(rng);
  };
  int y = 0;
  while (y < kSize - 120) {
    const int depth = uniform(120, 240);
    const int top = std::min(y + depth, kSize - 1);
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
    y = top + 40;  // a 2 m corridor above every band
  }
  fill(grid, 0, 0, kSize - 1, kWall - 1, OccupancyGrid::kOccupied);
  fill(grid, 0, kSize - kWall, kSize - 1, kSize - 1, OccupancyGrid::kOccupied);
  fill(grid, 0, 0, kWall - 1, kSize - 1, OccupancyGrid::kOccupied);
  fill(grid, kSize - kWall, 0, kSize - 1, kSize - 1, OccupancyGrid::kOccupied);
  return grid;
}

// Laser poses in free cells, so every scan starts where a robot could stand.
std::vector<geometry::Pose2D> free_poses(const OccupancyGrid& grid, int count) {
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

// One scan per iteration from a rotating set of poses (so the caches do not hold one scan's cells).
template <typename Scan>
void scan_loop(benchmark::State& state, const OccupancyGrid& grid, Scan scan) {
  const std::vector<geometry::Pose2D> poses = free_poses(grid, 256);
  std::vector<double> ranges_m(kBeams);
  std::size_t next = 0;
  for (auto _ : state) {
    const geometry::Pose2D& pose = poses[next++ % poses.size()];
    scan(pose, ranges_m);
    benchmark::DoNotOptimize(ranges_m.data());
    benchmark::ClobberMemory();
  }
  state.counters["beams/s"] = benchmark::Counter(static_cast<double>(state.iterations()) * kBeams,
                                                 benchmark::Counter::kIsRate);
}

void fan_scan(const RayCaster& caster, const geometry::Pose2D& pose,
              std::vector<double>& ranges_m) {
  caster.cast_fan({pose.x, pose.y}, pose.theta - std::numbers::pi / 2, kStep_rad, kRangeMax_m,
                  ranges_m);
}

void BM_ScanSynthetic2000(benchmark::State& state) {
  const OccupancyGrid grid = synthetic_office(1);
  const RayCaster caster(grid);
  scan_loop(state, grid, [&caster](const geometry::Pose2D& pose, std::vector<double>& ranges_m) {
    fan_scan(caster, pose, ranges_m);
  });
}
BENCHMARK(BM_ScanSynthetic2000)->Unit(benchmark::kMicrosecond);

// One cast() per beam (direction from sin/cos each time) on the same grid.
void BM_ScanSynthetic2000BeamByBeam(benchmark::State& state) {
  const OccupancyGrid grid = synthetic_office(1);
  const RayCaster caster(grid);
  scan_loop(state, grid, [&caster](const geometry::Pose2D& pose, std::vector<double>& ranges_m) {
    for (int i = 0; i < kBeams; ++i) {
      ranges_m[static_cast<std::size_t>(i)] =
          caster
              .cast({pose.x, pose.y}, pose.theta - std::numbers::pi / 2 + i * kStep_rad,
                    kRangeMax_m)
              .value_or(81.0);
    }
  });
}
BENCHMARK(BM_ScanSynthetic2000BeamByBeam)->Unit(benchmark::kMicrosecond);

// The plain cell-by-cell walk on the same grid, for comparison.
void BM_ScanSynthetic2000CellByCell(benchmark::State& state) {
  const OccupancyGrid grid = synthetic_office(1);
  const RayCaster caster(grid);
  scan_loop(state, grid, [&caster](const geometry::Pose2D& pose, std::vector<double>& ranges_m) {
    for (int i = 0; i < kBeams; ++i) {
      ranges_m[static_cast<std::size_t>(i)] =
          caster
              .cast_cell_by_cell({pose.x, pose.y},
                                 pose.theta - std::numbers::pi / 2 + i * kStep_rad, kRangeMax_m)
              .value_or(81.0);
    }
  });
}
BENCHMARK(BM_ScanSynthetic2000CellByCell)->Unit(benchmark::kMicrosecond);

// A 2000 x 2000 grid with one wall: nearly every beam flies to the border, the worst case for a
// plain DDA.
void BM_ScanOpen2000(benchmark::State& state) {
  OccupancyGrid grid(2000, 2000, 0.05, {}, OccupancyGrid::kFree);
  fill(grid, 0, 0, 1999, 2, OccupancyGrid::kOccupied);
  const RayCaster caster(grid);
  scan_loop(state, grid, [&caster](const geometry::Pose2D& pose, std::vector<double>& ranges_m) {
    fan_scan(caster, pose, ranges_m);
  });
}
BENCHMARK(BM_ScanOpen2000)->Unit(benchmark::kMicrosecond);

World office_world() {
  const std::filesystem::path worlds_dir = MOBOT_DEFAULT_WORLDS_DIR;
  return load_world(resolve_world(worlds_dir, "office"));
}

void BM_ScanOfficeWorld(benchmark::State& state) {
  const World world = office_world();
  const RayCaster caster(world.floor);
  scan_loop(state, world.floor,
            [&caster](const geometry::Pose2D& pose, std::vector<double>& ranges_m) {
              fan_scan(caster, pose, ranges_m);
            });
}
BENCHMARK(BM_ScanOfficeWorld)->Unit(benchmark::kMicrosecond);

void BM_BuildRayCaster2000(benchmark::State& state) {
  const OccupancyGrid grid = synthetic_office(1);
  for (auto _ : state) {
    RayCaster caster(grid);
    benchmark::DoNotOptimize(&caster);
  }
}
BENCHMARK(BM_BuildRayCaster2000)->Unit(benchmark::kMillisecond);

// One 50 Hz control tick of the simulated robot with a laser scan: circling (1 m radius) in the
// south-west room of the office, clear of its walls and table.
void BM_SimulatorStepAndLaser(benchmark::State& state) {
  Simulator sim(office_world(), r1_profile(), 7);
  sim.reset({6.0, 3.5, 0.0}, 7);
  for (auto _ : state) {
    sim.set_command({0.8, 0.8});
    sim.step(0.02);
    msgs::LaserScan scan = sim.read_laser();
    benchmark::DoNotOptimize(scan.ranges_m.data());
    // The wheel noise makes the circle wander; start over before it reaches a wall.
    if (sim.time_s() > 60.0) sim.reset({6.0, 3.5, 0.0}, 7);
  }
  state.counters["collisions"] = sim.collision_count();
}
BENCHMARK(BM_SimulatorStepAndLaser)->Unit(benchmark::kMicrosecond);

void BM_SimulatorStepOnly(benchmark::State& state) {
  Simulator sim(office_world(), r1_profile(), 7);
  sim.reset({6.0, 3.5, 0.0}, 7);
  for (auto _ : state) {
    sim.set_command({0.8, 0.8});
    sim.step(0.02);
    benchmark::DoNotOptimize(sim.true_pose());
    if (sim.time_s() > 60.0) sim.reset({6.0, 3.5, 0.0}, 7);
  }
  state.counters["collisions"] = sim.collision_count();
}
BENCHMARK(BM_SimulatorStepOnly)->Unit(benchmark::kMicrosecond);

// Driving into a wall every tick: the step bisects to the contact point each time.
void BM_SimulatorStepPushingAWall(benchmark::State& state) {
  Simulator sim(office_world(), r1_profile(), 7);
  sim.reset({2.0, 8.1, 1.5707963267948966}, 7);  // facing the corridor's north wall
  for (auto _ : state) {
    sim.set_command({0.5, 0.0});
    sim.step(0.02);
    benchmark::DoNotOptimize(sim.true_pose());
  }
  state.counters["collisions"] = sim.collision_count();
}
BENCHMARK(BM_SimulatorStepPushingAWall)->Unit(benchmark::kMicrosecond);

void BM_SimulatorSonar(benchmark::State& state) {
  Simulator sim(office_world(), r1_profile(), 7);
  for (auto _ : state) {
    msgs::SonarRing ring = sim.read_sonar();
    benchmark::DoNotOptimize(ring.readings.data());
  }
}
BENCHMARK(BM_SimulatorSonar)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace mobot::sim
