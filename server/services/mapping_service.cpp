#include "server/services/mapping_service.h"

#include "server/mapping/slam_estimator.h"
#include "server/services/after_commit.h"

namespace mobot::server {
namespace {

api::DomainError already_mapping() {
  return {api::ErrorKind::kConflict, "mapping_active", "a map is already being built"};
}

api::DomainError not_mapping() {
  return {api::ErrorKind::kConflict, "not_mapping", "no map is being built: start mapping first"};
}

}  // namespace

MappingService::MappingService(Runtime& runtime, Recorder& recorder, MapCatalog& catalog,
                               MappingStages stages)
    : runtime_(runtime), recorder_(recorder), catalog_(catalog), stages_(stages) {}

MappingService::~MappingService() = default;

api::MappingStatus MappingService::mapping_status() const {
  api::MappingStatus status;
  const auto session = stages_.mapping.session();
  if (!session) return status;
  const SlamWorkerStats stats = session->worker->stats();
  status.mapping = true;
  status.scans = static_cast<std::int64_t>(stats.slam.scans);
  status.nodes = static_cast<std::int64_t>(stats.slam.nodes);
  status.loop_closures = static_cast<std::int64_t>(stats.slam.loop_closures);
  status.started_t = session->started_s;
  return status;
}

void MappingService::start_mapping(api::Completion<api::MappingStatus> done) {
  runtime_.post([this, done = std::move(done)](TickContext& context) mutable {
    if (stages_.mapping.active()) return done(already_mapping());
    // The operator drives while mapping; a goal in progress would fight the joystick.
    stages_.navigate.end_active(navigation::GoalStatus::kCanceled, "mapping", context);
    const auto worker = stages_.mapping.start(context);
    stages_.estimate.substitute(std::make_unique<SlamEstimator>(worker, context.pose), context);
    context.event("mapping", {{"action", "start"},
                              {"x", context.pose.x},
                              {"y", context.pose.y},
                              {"theta", context.pose.theta}});
    api::MappingStatus status;
    status.mapping = true;
    status.started_t = context.now_s;
    after_commit(recorder_, context, std::move(done), status);
  });
}

void MappingService::stop_mapping(std::optional<std::string> save_as,
                                  api::Completion<api::MappingStopped> done) {
  runtime_.post(
      [this, save_as = std::move(save_as), done = std::move(done)](TickContext& context) mutable {
        if (!stages_.mapping.active()) return done(not_mapping());
        auto worker = stages_.mapping.end(context);
        // Localization goes on with the selected method from the SLAM's last pose; it gets the new
        // map when the catalog activates it.
        stages_.estimate.restore_selected(context);
        context.event("mapping", {{"action", save_as ? "save" : "discard"},
                                  {"scans", worker->stats().slam.scans},
                                  {"nodes", worker->stats().slam.nodes}});
        {
          std::lock_guard lock(retired_mutex_);
          retired_.push_back(worker);
        }
        if (!save_as)
          return after_commit(recorder_, context, std::move(done), api::MappingStopped{});
        context.then([this, worker, name = std::move(*save_as), done = std::move(done)]() mutable {
          worker->finish([this, name = std::move(name),
                          done = std::move(done)](mapping::OccupancyGrid grid) mutable {
            store(std::move(name), std::move(grid), std::move(done));
          });
        });
      });
}

void MappingService::store(std::string name, mapping::OccupancyGrid grid,
                           api::Completion<api::MappingStopped> done) {
  if (grid.width() == 0 || grid.height() == 0) {
    return done(api::DomainError{api::ErrorKind::kConflict, "empty_map",
                                 "the laser saw nothing while mapping: no map to save"});
  }
  const std::int64_t id = catalog_.import_map(name, grid);
  catalog_.activate_map(
      id, [this, id, done = std::move(done)](api::Result<api::MapInfo> result) mutable {
        if (!result.ok()) return done(result.error());
        runtime_.post([this, id, done = std::move(done)](TickContext& context) mutable {
          context.event("mapping", {{"action", "saved"}, {"map_id", id}});
          after_commit(recorder_, context, std::move(done), api::MappingStopped{id});
        });
      });
}

}  // namespace mobot::server
