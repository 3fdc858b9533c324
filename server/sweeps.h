#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include <boost/asio/thread_pool.hpp>

#include "api/robot_port.h"
#include "api/stream_hub.h"
#include "db/sweep_store.h"
#include "server/config.h"
#include "server/recorder.h"
#include "server/robot.h"

namespace mobot::server {

// The 3D sweeps of the API: accepts a sweep (stored before it is acknowledged), lets the Robot
// scan it on the control loop, then off the loop runs IPaBD on the cloud, merges the result into
// the planning map's 3D layer and stores the cloud and the IPaBD map. A sweep is "done" once all
// of that is on disk.
class Sweeps {
 public:
  Sweeps(const Config& config, db::SweepStore& store, Robot& robot, Recorder& recorder,
         api::StreamHub& hub);
  ~Sweeps();
  Sweeps(const Sweeps&) = delete;
  Sweeps& operator=(const Sweeps&) = delete;

  api::SweepInfo start(const api::SweepRequest& request);
  std::vector<api::SweepInfo> list() const;
  std::optional<api::SweepInfo> find(std::int64_t id) const;
  perception::PointCloud cloud(std::int64_t id) const;
  mapping::OccupancyGrid obstacle_map(std::int64_t id) const;
  // 404 unknown_sweep, 409 sweep_running.
  void remove(std::int64_t id);
  // Marks a sweep still running as failed (the server is stopping) and waits for the processing
  // of one that has finished scanning.
  void stop();

 private:
  void finish(const SweepOutcome& outcome);
  void record(double t_s, std::int64_t id, const std::string& status, nlohmann::json detail);
  api::SweepInfo with_progress(const db::SweepRecord& record) const;
  // 404 unknown_sweep, 409 sweep_not_done.
  void require_done(std::int64_t id) const;

  const SweepsSection options_;
  const double robot_height_m_;
  const double robot_width_m_;
  db::SweepStore& store_;
  Robot& robot_;
  Recorder& recorder_;
  api::StreamHub& hub_;

  mutable std::mutex mutex_;  // guards running_ and serialises start()
  std::optional<std::int64_t> running_;  // accepted and not yet done or failed
  boost::asio::thread_pool pool_{1};     // IPaBD and the final write, off the control loop
};

}  // namespace mobot::server
