#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "api/ports/result.h"

namespace mobot::api {

struct RunInfo {
  std::int64_t id = 0;
  std::string name;
  double started_unix_s = 0.0;
  std::optional<double> ended_unix_s;
  double distance_m = 0.0;
  int goals_succeeded = 0;
  int goals_failed = 0;
  int goals_canceled = 0;
};

struct TrajectoryPoint {
  double t_s, x, y, theta;
};

struct RunEvent {
  double t_s = 0.0;
  std::string kind;
  std::string detail_json;
};

// The recorded runs. Each read completes after what the current run has buffered is committed,
// so it sees everything acknowledged before it. Thread-safe.
class RunArchivePort {
 public:
  virtual ~RunArchivePort() = default;

  virtual void list_runs(Completion<std::vector<RunInfo>> done) const = 0;
  // kNotFound unknown_run.
  virtual void run_trajectory(std::int64_t id,
                              Completion<std::vector<TrajectoryPoint>> done) const = 0;
  virtual void run_events(std::int64_t id, Completion<std::vector<RunEvent>> done) const = 0;
};

}  // namespace mobot::api
