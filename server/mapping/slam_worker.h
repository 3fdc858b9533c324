#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "core/geometry/pose2d.h"
#include "core/mapping/map_tiles.h"
#include "core/mapping/occupancy_grid.h"
#include "core/msgs/laser_scan.h"
#include "core/slam/graph_slam.h"

namespace mobot::server {

struct SlamWorkerOptions {
  slam::GraphSlamOptions slam;
  slam::MapRenderOptions render;
  // The map is rendered and its changed tiles offered this often (robot clock: the scans' stamps),
  // or less often when rendering takes longer than a fifth of it (a large map).
  double map_period_s = 1.0;
  // Scans waiting for the matcher. A full queue drops the oldest: the pose goes on from odometry
  // and the next scan is matched with a wider gap, which the matcher's window absorbs.
  std::size_t max_queued_scans = 32;
};

// What the mapping session shows: the map so far and the tiles that changed since the last offer.
struct SlamMapUpdate {
  std::shared_ptr<const mapping::OccupancyGrid> grid;
  mapping::MapTileUpdate tiles;
};

struct SlamWorkerStats {
  slam::SlamStats slam;
  std::size_t dropped_scans = 0;
};

// The graph SLAM of one mapping session on a thread of its own: the control loop hands it scans
// with their odometry poses and reads the map -> odom correction back, never waiting for a match or
// an optimisation (docs/architecture.md: the tick never waits).
class SlamWorker {
 public:
  // The map frame is anchored so that the odometry pose `start_odom` is at `start_in_map`.
  // Throws std::invalid_argument on bad options.
  SlamWorker(const SlamWorkerOptions& options, const geometry::Pose2D& start_in_map,
             const geometry::Pose2D& start_odom);
  ~SlamWorker();
  SlamWorker(const SlamWorker&) = delete;
  SlamWorker& operator=(const SlamWorker&) = delete;

  // Any thread; never blocks on the matcher.
  void submit(const msgs::LaserScan& scan, const geometry::Pose2D& odom_pose);
  geometry::Pose2D map_from_odom() const;
  SlamWorkerStats stats() const;
  // The newest map update not taken yet, if any.
  std::optional<SlamMapUpdate> take_map_update();
  // Matches what is queued, renders the final map and hands it to `done` on the worker's thread;
  // later scans are ignored. Once only.
  void finish(std::function<void(mapping::OccupancyGrid)> done);

 private:
  struct QueuedScan {
    msgs::LaserScan scan;
    geometry::Pose2D odom_pose;
  };

  void run();
  void process(const QueuedScan& queued);
  void render_if_due(double stamp_s);

  const SlamWorkerOptions options_;
  slam::GraphSlam slam_;        // the worker thread's only
  mapping::MapTiler tiler_;     // the worker thread's only
  double next_render_s_ = 0.0;  // the worker thread's only

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<QueuedScan> queue_;
  bool finishing_ = false;
  std::function<void(mapping::OccupancyGrid)> on_finished_;
  geometry::Pose2D map_from_odom_;
  SlamWorkerStats stats_;
  std::optional<SlamMapUpdate> map_update_;
  std::thread thread_;
};

}  // namespace mobot::server
