#pragma once

#include "api/ports/run_archive_port.h"
#include "db/run_store.h"
#include "server/recorder.h"
#include "server/runtime.h"

namespace mobot::server {

// The RunArchivePort: each read waits (without blocking a thread) until what the current run has
// buffered is committed, then reads the store on the recorder's writer thread.
class RunArchive final : public api::RunArchivePort {
 public:
  RunArchive(db::RunStore& runs, Recorder& recorder, const Runtime& runtime)
      : runs_(runs), recorder_(recorder), runtime_(runtime) {}

  void list_runs(api::Completion<std::vector<api::RunInfo>> done) const override;
  void run_trajectory(std::int64_t id,
                      api::Completion<std::vector<api::TrajectoryPoint>> done) const override;
  void run_events(std::int64_t id, api::Completion<std::vector<api::RunEvent>> done) const override;

 private:
  db::RunStore& runs_;
  Recorder& recorder_;
  const Runtime& runtime_;
};

}  // namespace mobot::server
