#pragma once

#include <memory>

#include "server/latest.h"
#include "server/mapping/slam_worker.h"
#include "server/stage.h"

namespace mobot::server {

// A running mapping session: its SLAM worker and when it started (robot clock).
struct MappingSession {
  std::shared_ptr<SlamWorker> worker;
  double started_s = 0.0;
};

// The mapping session, if one runs (docs/algorithms.md E5, C7): tells the tick it is mapping and
// streams the growing map's changed tiles as the SLAM worker renders them. Starting and stopping
// are the mapping service's, on the control loop.
class MappingStage final : public Stage {
 public:
  explicit MappingStage(SlamWorkerOptions options) : options_(std::move(options)) {}

  std::string_view name() const override { return "mapping"; }
  void step(TickContext& context) override;

  bool active() const { return worker_ != nullptr; }
  // A new session anchored at the current estimate; the worker the SLAM estimator feeds.
  std::shared_ptr<SlamWorker> start(TickContext& context);
  // Ends the session; the worker, to be finished by the caller.
  std::shared_ptr<SlamWorker> end(TickContext& context);
  // Any thread: the running session, or null.
  std::shared_ptr<const MappingSession> session() const { return session_.load(); }

 private:
  SlamWorkerOptions options_;
  std::shared_ptr<SlamWorker> worker_;  // the loop's
  Latest<MappingSession> session_;
};

}  // namespace mobot::server
