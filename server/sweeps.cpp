#include "server/sweeps.h"

#include <boost/asio/post.hpp>
#include <chrono>
#include <numbers>
#include <spdlog/spdlog.h>

#include "api/api_error.h"
#include "core/perception/ipabd.h"
#include "core/perception/tilt_sweep.h"

namespace mobot::server {
namespace {

double unix_now_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

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

Sweeps::Sweeps(const Config& config, db::SweepStore& store, Robot& robot, Recorder& recorder,
               api::StreamHub& hub)
    : options_(config.sweeps),
      robot_height_m_(sim::r1_profile().height_m),
      robot_width_m_(sim::r1_profile().footprint_width_m),
      store_(store),
      robot_(robot),
      recorder_(recorder),
      hub_(hub) {
  if (const int interrupted = store_.fail_interrupted("interrupted"); interrupted > 0) {
    spdlog::warn("{} 3D sweep(s) of an earlier process never finished: marked failed",
                 interrupted);
  }
  robot_.set_sweep_listener([this](SweepOutcome outcome) {
    // On the control loop under the Robot's mutex: only hand it on.
    auto shared = std::make_shared<const SweepOutcome>(std::move(outcome));
    boost::asio::post(pool_, [this, shared] { finish(*shared); });
  });
}

Sweeps::~Sweeps() { pool_.join(); }

api::SweepInfo Sweeps::start(const api::SweepRequest& request) {
  const auto mode = perception::find_sweep_mode(request.period_s, request.step_deg);
  if (!mode) {
    throw api::ApiError(400, "invalid_mode",
                        "period_s must be 10 or 42 and step_deg 1, 0.5 or 0.25 (Table 2.1)");
  }
  std::lock_guard lock(mutex_);
  if (running_) {
    throw api::ApiError(409, "sweep_running",
                        "3D sweep " + std::to_string(*running_) + " is running: wait until it is done");
  }
  const double now_s = robot_.time_s();
  const std::int64_t id = store_.insert_running(mode->period_s, mode->step_deg, mode->scans, now_s,
                                                unix_now_s(), recorder_.run_id());
  try {
    robot_.start_sweep(id, *mode);
  } catch (...) {
    store_.fail(id, now_s, "not_started");
    throw;
  }
  running_ = id;
  record(now_s, id, "running",
         {{"period_s", mode->period_s}, {"step_deg", mode->step_deg}, {"scans", mode->scans}});
  return with_progress(*store_.get(id));
}

void Sweeps::finish(const SweepOutcome& outcome) {
  try {
    if (outcome.failure) {
      store_.fail(outcome.id, outcome.ended_s, *outcome.failure);
      record(outcome.ended_s, outcome.id, "failed", {{"reason", *outcome.failure}});
    } else {
      const auto sweep = store_.get(outcome.id);
      perception::IpabdOptions ipabd;
      ipabd.robot_height_m = robot_height_m_;
      ipabd.floor_tolerance_m = options_.floor_tolerance_m;
      ipabd.max_range_m = options_.max_range_m;
      ipabd.pdbs_c0_m = options_.pdbs_c0_m;
      ipabd.pdbs_c1 = options_.pdbs_c1;
      ipabd.robot_diameter_m = robot_width_m_;
      ipabd.dilation_radius_m = robot_width_m_ / 2.0;
      // Step 2 keeps one point per beam of the laser.
      ipabd.bearing_step_rad = (sweep ? sweep->step_deg : 1.0) * std::numbers::pi / 180.0;
      ipabd.lattice_origin = robot_.obstacle_lattice();
      const perception::IpabdResult result =
          perception::run_ipabd(outcome.cloud, outcome.origin_in_map, ipabd);
      std::optional<int> layer_cells;
      if (options_.obstacle_layer) {
        layer_cells = robot_.apply_3d_obstacles(result.obstacles, outcome.map_generation);
      }
      store_.finish(outcome.id, outcome.ended_s, outcome.cloud, result.dilated);
      nlohmann::json detail{{"points", outcome.cloud.size()},
                            {"ipabd_bins", result.bins.size()},
                            {"ipabd_segments", result.segments.size()}};
      if (layer_cells) detail["layer_occupied_cells"] = *layer_cells;
      record(outcome.ended_s, outcome.id, "done", std::move(detail));
    }
  } catch (const std::exception& error) {
    spdlog::error("3D sweep {}: {}", outcome.id, error.what());
    try {
      store_.fail(outcome.id, outcome.ended_s, std::string("processing_failed: ") + error.what());
    } catch (const std::exception& db_error) {
      spdlog::error("3D sweep {}: cannot mark it failed: {}", outcome.id, db_error.what());
    }
  }
  std::lock_guard lock(mutex_);
  if (running_ == outcome.id) running_.reset();
}

void Sweeps::record(double t_s, std::int64_t id, const std::string& status,
                    nlohmann::json detail) {
  detail["id"] = id;
  detail["status"] = status;
  recorder_.record_event(t_s, "sweep", detail.dump());
  hub_.publish_event(t_s, "sweep", detail);
}

api::SweepInfo Sweeps::with_progress(const db::SweepRecord& record) const {
  api::SweepInfo info = to_info(record);
  if (record.status != "running") return info;
  const auto progress = robot_.sweep_progress();
  if (progress && progress->id == record.id) {
    info.scans_done = progress->scans_done;
    info.points = static_cast<std::int64_t>(progress->points);
  } else {
    info.scans_done = info.scans;  // scanned; IPaBD and the write are under way
  }
  return info;
}

std::vector<api::SweepInfo> Sweeps::list() const {
  std::vector<api::SweepInfo> out;
  for (const auto& record : store_.list()) out.push_back(with_progress(record));
  return out;
}

std::optional<api::SweepInfo> Sweeps::find(std::int64_t id) const {
  const auto record = store_.get(id);
  if (!record) return std::nullopt;
  return with_progress(*record);
}

void Sweeps::require_done(std::int64_t id) const {
  const auto record = store_.get(id);
  if (!record) throw api::ApiError(404, "unknown_sweep", "no 3D sweep " + std::to_string(id));
  if (record->status != "done") {
    throw api::ApiError(409, "sweep_not_done",
                        "3D sweep " + std::to_string(id) + " is " + record->status +
                            (record->reason.empty() ? "" : " (" + record->reason + ")") +
                            ": it has no cloud");
  }
}

perception::PointCloud Sweeps::cloud(std::int64_t id) const {
  require_done(id);
  return store_.cloud(id).value_or(perception::PointCloud{});
}

mapping::OccupancyGrid Sweeps::obstacle_map(std::int64_t id) const {
  require_done(id);
  return store_.obstacle_map(id).value_or(mapping::OccupancyGrid{});
}

void Sweeps::remove(std::int64_t id) {
  switch (store_.remove(id)) {
    case db::SweepStore::RemoveResult::kRemoved:
      return;
    case db::SweepStore::RemoveResult::kNotFound:
      throw api::ApiError(404, "unknown_sweep", "no 3D sweep " + std::to_string(id));
    case db::SweepStore::RemoveResult::kRunning:
      throw api::ApiError(409, "sweep_running",
                          "3D sweep " + std::to_string(id) + " is running: wait until it is done");
  }
}

void Sweeps::stop() {
  pool_.join();
  std::lock_guard lock(mutex_);
  if (!running_) return;
  try {
    store_.fail(*running_, robot_.time_s(), "server_stopped");
  } catch (const std::exception& error) {
    spdlog::error("3D sweep {}: cannot mark it failed: {}", *running_, error.what());
  }
  running_.reset();
}

}  // namespace mobot::server
