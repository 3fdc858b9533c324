#include "server/mapping/slam_worker.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace mobot::server {
namespace {

// The renderer aligns the map's origin to whole tiles of the lattice the tiler cuts.
int tile_cells_of(const slam::MapRenderOptions& render) {
  const double cells = render.align_m / render.resolution_m;
  if (render.align_m <= 0.0 || std::abs(cells - std::round(cells)) > 1e-6) {
    throw std::invalid_argument("the map's alignment must be a whole number of cells");
  }
  return static_cast<int>(std::round(cells));
}

}  // namespace

SlamWorker::SlamWorker(const SlamWorkerOptions& options, const geometry::Pose2D& start_in_map,
                       const geometry::Pose2D& start_odom)
    : options_(options),
      slam_(options.slam),
      tiler_(tile_cells_of(options.render), {}),
      map_from_odom_(geometry::compose(start_in_map, geometry::inverse(start_odom))) {
  slam_.set_start_pose(start_in_map);
  thread_ = std::thread([this] { run(); });
}

SlamWorker::~SlamWorker() {
  {
    std::lock_guard lock(mutex_);
    finishing_ = true;
    queue_.clear();
  }
  wake_.notify_all();
  thread_.join();
}

void SlamWorker::submit(const msgs::LaserScan& scan, const geometry::Pose2D& odom_pose) {
  {
    std::lock_guard lock(mutex_);
    if (finishing_) return;
    if (queue_.size() >= options_.max_queued_scans) {
      queue_.pop_front();
      ++stats_.dropped_scans;
    }
    queue_.push_back({scan, odom_pose});
  }
  wake_.notify_one();
}

geometry::Pose2D SlamWorker::map_from_odom() const {
  std::lock_guard lock(mutex_);
  return map_from_odom_;
}

SlamWorkerStats SlamWorker::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

std::optional<SlamMapUpdate> SlamWorker::take_map_update() {
  std::lock_guard lock(mutex_);
  std::optional<SlamMapUpdate> out = std::move(map_update_);
  map_update_.reset();
  return out;
}

void SlamWorker::finish(std::function<void(mapping::OccupancyGrid)> done) {
  {
    std::lock_guard lock(mutex_);
    if (finishing_) return;
    finishing_ = true;
    on_finished_ = std::move(done);
  }
  wake_.notify_all();
}

void SlamWorker::run() {
  for (;;) {
    std::unique_lock lock(mutex_);
    wake_.wait(lock, [this] { return finishing_ || !queue_.empty(); });
    if (queue_.empty()) {
      // Finishing, with every scan matched: the final map, rendered from the optimised graph.
      auto done = std::move(on_finished_);
      lock.unlock();
      if (done) done(slam_.render_map(options_.render));
      return;
    }
    QueuedScan next = std::move(queue_.front());
    queue_.pop_front();
    lock.unlock();
    process(next);
  }
}

void SlamWorker::process(const QueuedScan& queued) {
  try {
    slam_.add_scan(queued.scan, queued.odom_pose);
  } catch (const std::invalid_argument& error) {
    spdlog::warn("slam: scan at t={:.3f} refused: {}", queued.scan.stamp_s, error.what());
    return;
  }
  {
    std::lock_guard lock(mutex_);
    map_from_odom_ = slam_.map_from_odom();
    stats_.slam = slam_.stats();
  }
  render_if_due(queued.scan.stamp_s);
}

void SlamWorker::render_if_due(double stamp_s) {
  if (stamp_s < next_render_s_) return;
  const auto started = std::chrono::steady_clock::now();
  auto grid = std::make_shared<const mapping::OccupancyGrid>(slam_.render_map(options_.render));
  SlamMapUpdate update{grid, tiler_.changed_tiles(*grid)};
  const double took_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  // Rendering a large map may take a while: never more than a fifth of the worker's time.
  next_render_s_ = stamp_s + std::max(options_.map_period_s, 5.0 * took_s);
  std::lock_guard lock(mutex_);
  if (map_update_) {
    // Not taken yet: the tiles changed since the last taken update are the union.
    for (auto& tile : update.tiles.tiles) map_update_->tiles.tiles.push_back(std::move(tile));
    map_update_->grid = update.grid;
  } else {
    map_update_ = std::move(update);
  }
}

}  // namespace mobot::server
