// One control tick of mobotd's whole pipeline on the simulated R1 robot in the office world:
// simulator step and sensors (laser ray casting at its 10 Hz), odometry, EKF with compass, laser
// lines and bearings, goal navigation (tracker + sonar supervisor), command mux, smoother, the bus
// with the recorder subscribed. No stream client is attached (the fan-out is measured by
// mobot_stream_load). Issue target: < 1 ms per tick; the laser ticks (every 5th) are the heavy
// ones.
#include <benchmark/benchmark.h>

#include <atomic>
#include <thread>

#include "db/database.h"
#include "db/run_store.h"
#include "drivers/backend_factory.h"
#include "server/bus_bridges.h"
#include "server/config.h"
#include "server/recorder.h"
#include "server/robot_assembly.h"
#include "server/services/control_service.h"

namespace mobot::server {
namespace {

// Runs the loop's posted commands until the goal request has its answer.
bool submit(ControlService& control, Runtime& runtime, const api::GoalRequest& request) {
  std::atomic<int> outcome{0};
  control.submit_goal(
      request, [&](api::Result<navigation::Goal> result) { outcome = result.ok() ? 1 : -1; });
  while (outcome == 0) {
    runtime.run_posted();
    std::this_thread::yield();
  }
  return outcome > 0;
}

void BM_ControlTickWithGoal(benchmark::State& state) {
  Config config;
  db::Database database = db::Database::open_in_memory();
  db::RunStore runs(database);
  Recorder recorder(runs, runs.start_run("bench", 0.0), 200);
  Bus bus;
  connect_recorder(bus, recorder, config.recorder.trajectory_rate_hz);
  drivers::BackendOptions backend;
  backend.world = "office";
  RobotAssembly robot(config, bus, drivers::make_backend(backend), {});
  Runtime& runtime = robot.runtime();
  const ActiveMap map{1, 1,
                      std::make_shared<const mapping::OccupancyGrid>(
                          robot.backend().sim_control()->surveyed_map())};
  for (auto* listener : robot.map_listeners()) listener->prepare_map(map);
  runtime.post([&](TickContext& context) {
    for (auto* listener : robot.map_listeners()) listener->apply_map(map, context);
  });
  runtime.run_posted();
  ControlService control(runtime, recorder,
                         {robot.mux(), robot.navigate(), robot.estimate(), robot.write_base()},
                         robot.kinematics(), robot.plugins());
  api::GoalRequest far_goal;
  far_goal.target = {17.0, 7.5, 0.0};
  api::GoalRequest near_goal;
  near_goal.target = {3.0, 7.5, 0.0};
  submit(control, runtime, far_goal);
  std::int64_t ticks = 0;
  for (auto _ : state) {
    runtime.tick();
    // Keep a goal running: when one ends, the next heads the other way.
    if (++ticks % 500 == 0 && runtime.state()->robot.mode != "navigating") {
      state.PauseTiming();
      submit(control, runtime, ticks % 1000 == 0 ? far_goal : near_goal);
      state.ResumeTiming();
    }
  }
  state.counters["mode_navigating"] = runtime.state()->robot.mode == "navigating" ? 1 : 0;
}
BENCHMARK(BM_ControlTickWithGoal)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace mobot::server
