// One control tick of mobotd's whole pipeline on the simulated R1 robot in the office world:
// simulator step and sensors (laser ray casting at its 10 Hz), odometry, EKF with compass, laser
// lines and bearings, goal navigation (tracker + sonar supervisor), command mux, smoother, and the
// recorder. No stream client is attached (the fan-out is measured by mobot_stream_load). Issue
// target: < 1 ms per tick; the laser ticks (every 5th) are the heavy ones.
#include <benchmark/benchmark.h>

#include "api/stream_hub.h"
#include "db/database.h"
#include "db/run_store.h"
#include "drivers/sim/world.h"
#include "server/config.h"
#include "server/recorder.h"
#include "server/robot.h"

namespace mobot::server {
namespace {

void BM_ControlTickWithGoal(benchmark::State& state) {
  Config config;
  db::Database database = db::Database::open_in_memory();
  db::RunStore runs(database);
  Recorder recorder(runs, runs.start_run("bench", 0.0), 200);
  api::StreamHub hub({});
  sim::World world =
      sim::load_world(sim::resolve_world(MOBOT_DEFAULT_WORLDS_DIR, "office"));
  const mapping::OccupancyGrid floor = world.floor;
  Robot robot(config, std::move(world), hub, recorder);
  robot.set_map(floor);
  api::GoalRequest far_goal;
  far_goal.target = {17.0, 7.5, 0.0};
  api::GoalRequest near_goal;
  near_goal.target = {3.0, 7.5, 0.0};
  robot.submit_goal(far_goal);
  std::int64_t ticks = 0;
  for (auto _ : state) {
    robot.tick();
    // Keep a goal running: when one ends, the next heads the other way.
    if (++ticks % 500 == 0 && robot.snapshot().mode != "navigating") {
      state.PauseTiming();
      robot.submit_goal(ticks % 1000 == 0 ? far_goal : near_goal);
      state.ResumeTiming();
    }
  }
  state.counters["mode_navigating"] = robot.snapshot().mode == "navigating" ? 1 : 0;
}
BENCHMARK(BM_ControlTickWithGoal)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace mobot::server
