#include "server/services/run_archive.h"

namespace mobot::server {
namespace {

api::DomainError unknown_run() {
  return {api::ErrorKind::kNotFound, "unknown_run", "no run with this id"};
}

// Runs `read` after the recorder's next commit and hands its result (or its failure) to `done`.
template <class T, class Read>
void read_after_commit(Recorder& recorder, api::Completion<T> done, Read read) {
  recorder.flush_async([done = std::move(done), read = std::move(read)]() mutable {
    try {
      done(read());
    } catch (const api::DomainException& error) {
      done(error.error());
    }
  });
}

}  // namespace

void RunArchive::list_runs(api::Completion<std::vector<api::RunInfo>> done) const {
  // The current run's goal counts come from its events: the ones still buffered count too.
  read_after_commit(recorder_, std::move(done), [this] {
    std::vector<api::RunInfo> out;
    for (const auto& run : runs_.list()) {
      out.push_back({run.id, run.name, run.started_unix_s, run.ended_unix_s, run.distance_m,
                     run.goals.succeeded, run.goals.failed, run.goals.canceled});
    }
    // The current run's distance is live, not as of the last flush.
    for (auto& run : out) {
      if (run.id == recorder_.run_id()) run.distance_m = runtime_.state()->distance_m;
    }
    return out;
  });
}

void RunArchive::run_trajectory(std::int64_t id,
                                api::Completion<std::vector<api::TrajectoryPoint>> done) const {
  read_after_commit(recorder_, std::move(done), [this, id] {
    if (!runs_.get(id)) throw api::DomainException(unknown_run());
    std::vector<api::TrajectoryPoint> out;
    for (const auto& sample : runs_.trajectory(id)) {
      out.push_back({sample.t_s, sample.x, sample.y, sample.theta});
    }
    return out;
  });
}

void RunArchive::run_events(std::int64_t id,
                            api::Completion<std::vector<api::RunEvent>> done) const {
  read_after_commit(recorder_, std::move(done), [this, id] {
    if (!runs_.get(id)) throw api::DomainException(unknown_run());
    std::vector<api::RunEvent> out;
    for (const auto& event : runs_.events(id))
      out.push_back({event.t_s, event.kind, event.detail_json});
    return out;
  });
}

}  // namespace mobot::server
