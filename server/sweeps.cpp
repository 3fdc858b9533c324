#include "server/sweeps.h"

#include "server/wall_clock.h"

#include <spdlog/spdlog.h>
#include <boost/asio/post.hpp>
#include <chrono>
#include <numbers>

#include <algorithm>
#include "core/perception/ipabd.h"
#include "core/perception/tilt_sweep.h"

namespace mobot::server {
namespace {

api::SweepInfo to_info(const db::SweepRecord& record) {
  api::SweepInfo info;
  info.id = record.id;
  info.status = record.status;
  info.reason = record.reason;
  info.period_s = record.period_s;
  info.step_deg = record.step_deg;
  info.scans = record.scans;
  info.scans_done = record.status == "done" ? record.scans : 0;
  info.points = record.points;
  info.started_t = record.started_t;
  info.ended_t = record.ended_t;
  return info;
}

}  // namespace

Sweeps::Sweeps(const SweepsSection& options, SweepRobot robot, db::SweepStore& store,
               std::int64_t run_id, Runtime& runtime, Bus& bus, SweepLayer& layer,
               PlanningWorker& planning)
    : options_(options),
      robot_(robot),
      store_(store),
      run_id_(run_id),
      runtime_(runtime),
      bus_(bus),
      layer_(layer),
      planning_(planning) {
  if (const int interrupted = store_.fail_interrupted("interrupted"); interrupted > 0) {
    spdlog::warn("{} 3D sweep(s) of an earlier process never finished: marked failed", interrupted);
  }
}

Sweeps::~Sweeps() { pool_.join(); }

void Sweeps::on_outcome(SweepOutcome outcome) {
  auto shared = std::make_shared<const SweepOutcome>(std::move(outcome));
  boost::asio::post(pool_, [this, shared] { finish(*shared); });
}

void Sweeps::start_sweep(const api::SweepRequest& request, api::Completion<api::SweepInfo> done) {
  const auto mode = perception::find_sweep_mode(request.period_s, request.step_deg);
  if (!mode) {
    return done(api::DomainError{
        api::ErrorKind::kInvalid, "invalid_mode",
        "period_s must be 10 or 42 and step_deg 1, 0.5 or 0.25 (the tilt unit's modes)"});
  }
  if (!stage_) {
    return done(api::DomainError{api::ErrorKind::kConflict, "no_tilt_laser",
                                 "this robot has no tilting laser"});
  }
  std::lock_guard lock(mutex_);
  if (running_) {
    return done(api::DomainError{
        api::ErrorKind::kConflict, "sweep_running",
        "3D sweep " + std::to_string(*running_) + " is running: wait until it is done"});
  }
  const double now_s = runtime_.state()->robot.t_s;
  const std::int64_t id = store_.insert_running(mode->period_s, mode->step_deg, mode->scans, now_s,
                                                unix_now_s(), run_id_);
  running_ = id;
  runtime_.post([this, id, mode = *mode, done = std::move(done)](TickContext& context) mutable {
    if (!stage_->start(id, mode, context)) {
      store_.fail(id, context.now_s, "not_started");
      {
        std::lock_guard running_lock(mutex_);
        if (running_ == id) running_.reset();
      }
      return done(api::DomainError{api::ErrorKind::kConflict, "sweep_running",
                                   "a 3D sweep is running: wait until it is done"});
    }
    record(context.now_s, id, "running",
           {{"period_s", mode.period_s}, {"step_deg", mode.step_deg}, {"scans", mode.scans}});
    context.then(
        [this, id, done = std::move(done)]() mutable { done(with_progress(*store_.get(id))); });
  });
}

template <class Write>
void Sweeps::conclude(std::int64_t id, Write write) {
  // The stored status and running_ change together: a client that reads "done" may start the
  // next sweep at once.
  std::lock_guard lock(mutex_);
  write();
  if (running_ == id) running_.reset();
}

void Sweeps::finish(const SweepOutcome& outcome) {
  try {
    if (outcome.failure) {
      conclude(outcome.id, [&] { store_.fail(outcome.id, outcome.ended_s, *outcome.failure); });
      record(outcome.ended_s, outcome.id, "failed", {{"reason", *outcome.failure}});
    } else {
      const auto sweep = store_.get(outcome.id);
      perception::IpabdOptions ipabd;
      ipabd.robot_height_m = robot_.height_m;
      ipabd.floor_tolerance_m = options_.floor_tolerance_m;
      ipabd.max_range_m = options_.max_range_m;
      ipabd.pdbs_c0_m = options_.pdbs_c0_m;
      ipabd.pdbs_c1 = options_.pdbs_c1;
      ipabd.robot_diameter_m = robot_.width_m;
      ipabd.dilation_radius_m = robot_.width_m / 2.0;
      // Step 2 keeps one point per beam of the laser.
      ipabd.bearing_step_rad = (sweep ? sweep->step_deg : 1.0) * std::numbers::pi / 180.0;
      ipabd.lattice_origin = layer_.lattice_origin();
      const perception::IpabdResult result =
          perception::run_ipabd(outcome.cloud, outcome.origin_in_map, ipabd);
      std::optional<int> layer_cells;
      if (options_.obstacle_layer)
        layer_cells = merge_layer(result.obstacles, outcome.map_generation);
      conclude(outcome.id,
               [&] { store_.finish(outcome.id, outcome.ended_s, outcome.cloud, result.dilated); });
      nlohmann::json detail{{"points", outcome.cloud.size()},
                            {"ipabd_bins", result.bins.size()},
                            {"ipabd_segments", result.segments.size()}};
      if (layer_cells) detail["layer_occupied_cells"] = *layer_cells;
      record(outcome.ended_s, outcome.id, "done", std::move(detail));
    }
  } catch (const std::exception& error) {
    spdlog::error("3D sweep {}: {}", outcome.id, error.what());
    try {
      conclude(outcome.id, [&] {
        store_.fail(outcome.id, outcome.ended_s, std::string("processing_failed: ") + error.what());
      });
    } catch (const std::exception& db_error) {
      spdlog::error("3D sweep {}: cannot mark it failed: {}", outcome.id, db_error.what());
    }
  }
  std::lock_guard lock(mutex_);
  if (running_ == outcome.id) running_.reset();
}

std::optional<int> Sweeps::merge_layer(const mapping::OccupancyGrid& observed,
                                       std::uint64_t map_generation) {
  const auto layer = layer_.merge(observed, map_generation);
  // Re-inflating the map with the layer takes a while: here, off the control loop.
  if (!layer || !planning_.set_obstacle_layer(*layer, map_generation)) return std::nullopt;
  return static_cast<int>(std::count((*layer)->cells().begin(), (*layer)->cells().end(),
                                     mapping::OccupancyGrid::kOccupied));
}

void Sweeps::record(double t_s, std::int64_t id, const std::string& status, nlohmann::json detail) {
  detail["id"] = id;
  detail["status"] = status;
  bus_.events.publish({t_s, "sweep", std::move(detail)});
  bus_.flush.publish({t_s});
}

api::SweepInfo Sweeps::with_progress(const db::SweepRecord& record) const {
  api::SweepInfo info = to_info(record);
  if (record.status != "running") return info;
  const auto progress = runtime_.state()->sweep;
  if (progress && progress->id == record.id) {
    info.scans_done = progress->scans_done;
    info.points = static_cast<std::int64_t>(progress->points);
  } else {
    info.scans_done = info.scans;  // scanned; IPaBD and the write are under way
  }
  return info;
}

std::vector<api::SweepInfo> Sweeps::list_sweeps() const {
  std::vector<api::SweepInfo> out;
  for (const auto& record : store_.list()) out.push_back(with_progress(record));
  return out;
}

std::optional<api::SweepInfo> Sweeps::find_sweep(std::int64_t id) const {
  const auto record = store_.get(id);
  if (!record) return std::nullopt;
  return with_progress(*record);
}

void Sweeps::require_done(std::int64_t id) const {
  const auto record = store_.get(id);
  if (!record)
    throw api::DomainException(api::ErrorKind::kNotFound, "unknown_sweep",
                               "no 3D sweep " + std::to_string(id));
  if (record->status != "done") {
    throw api::DomainException(api::ErrorKind::kConflict, "sweep_not_done",
                               "3D sweep " + std::to_string(id) + " is " + record->status +
                                   (record->reason.empty() ? "" : " (" + record->reason + ")") +
                                   ": it has no cloud");
  }
}

perception::PointCloud Sweeps::sweep_cloud(std::int64_t id) const {
  require_done(id);
  return store_.cloud(id).value_or(perception::PointCloud{});
}

mapping::OccupancyGrid Sweeps::sweep_obstacle_map(std::int64_t id) const {
  require_done(id);
  return store_.obstacle_map(id).value_or(mapping::OccupancyGrid{});
}

void Sweeps::delete_sweep(std::int64_t id) {
  switch (store_.remove(id)) {
    case db::SweepStore::RemoveResult::kRemoved:
      return;
    case db::SweepStore::RemoveResult::kNotFound:
      throw api::DomainException(api::ErrorKind::kNotFound, "unknown_sweep",
                                 "no 3D sweep " + std::to_string(id));
    case db::SweepStore::RemoveResult::kRunning:
      throw api::DomainException(
          api::ErrorKind::kConflict, "sweep_running",
          "3D sweep " + std::to_string(id) + " is running: wait until it is done");
  }
}

void Sweeps::stop() {
  pool_.join();
  std::lock_guard lock(mutex_);
  if (!running_) return;
  try {
    store_.fail(*running_, runtime_.state()->robot.t_s, "server_stopped");
  } catch (const std::exception& error) {
    spdlog::error("3D sweep {}: cannot mark it failed: {}", *running_, error.what());
  }
  running_.reset();
}

}  // namespace mobot::server
