#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include <boost/asio/thread_pool.hpp>

#include "api/ports/sweeps_port.h"
#include "db/sweep_store.h"
#include "server/bus.h"
#include "server/config.h"
#include "server/planning_worker.h"
#include "server/runtime.h"
#include "server/stages/sweep_stage.h"
#include "server/sweep_layer.h"

namespace mobot::server {

// What the sweeps' processing needs of the robot.
struct SweepRobot {
  double height_m = 0.0;
  double width_m = 0.0;
};

// The SweepsPort: accepts a sweep (stored before it is acknowledged), has the sweep stage scan it
// on the control loop, then off the loop runs IPaBD on the cloud, merges the result into the 3D
// layer the planner uses and stores the cloud and the IPaBD map. A sweep is "done" once all of
// that is on disk.
class Sweeps final : public api::SweepsPort {
 public:
  Sweeps(const SweepsSection& options, SweepRobot robot, db::SweepStore& store, std::int64_t run_id,
         Runtime& runtime, Bus& bus, SweepLayer& layer, PlanningWorker& planning);
  ~Sweeps() override;
  Sweeps(const Sweeps&) = delete;
  Sweeps& operator=(const Sweeps&) = delete;

  // The sweep stage's listener: hands the outcome to the processing thread.
  void on_outcome(SweepOutcome outcome);
  // Wired after construction: the stage needs the listener, this needs the stage.
  void set_stage(SweepStage& stage) { stage_ = &stage; }

  void start_sweep(const api::SweepRequest& request, api::Completion<api::SweepInfo> done) override;
  std::vector<api::SweepInfo> list_sweeps() const override;
  std::optional<api::SweepInfo> find_sweep(std::int64_t id) const override;
  perception::PointCloud sweep_cloud(std::int64_t id) const override;
  mapping::OccupancyGrid sweep_obstacle_map(std::int64_t id) const override;
  void delete_sweep(std::int64_t id) override;
  // Marks a sweep still running as failed (the server is stopping) and waits for the processing
  // of one that has finished scanning.
  void stop();

 private:
  void finish(const SweepOutcome& outcome);
  template <class Write>
  void conclude(std::int64_t id, Write write);
  std::optional<int> merge_layer(const mapping::OccupancyGrid& observed,
                                 std::uint64_t map_generation);
  void record(double t_s, std::int64_t id, const std::string& status, nlohmann::json detail);
  api::SweepInfo with_progress(const db::SweepRecord& record) const;
  // kNotFound unknown_sweep, kConflict sweep_not_done.
  void require_done(std::int64_t id) const;

  const SweepsSection options_;
  const SweepRobot robot_;
  db::SweepStore& store_;
  const std::int64_t run_id_;
  Runtime& runtime_;
  Bus& bus_;
  SweepLayer& layer_;
  PlanningWorker& planning_;
  SweepStage* stage_ = nullptr;

  mutable std::mutex mutex_;             // guards running_ and serialises start()
  std::optional<std::int64_t> running_;  // accepted and not yet done or failed
  boost::asio::thread_pool pool_{1};     // IPaBD and the final write, off the control loop
};

}  // namespace mobot::server
