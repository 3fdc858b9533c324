#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "db/database.h"

namespace mobot::db {

struct TrajectorySample {
  double t_s = 0.0;  // robot clock
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;
};

struct EventRecord {
  double t_s = 0.0;
  std::string kind;
  std::string detail_json;
};

struct GoalCounts {
  int succeeded = 0;
  int failed = 0;
  int canceled = 0;
};

struct RunRecord {
  std::int64_t id = 0;
  std::string name;
  double started_unix_s = 0.0;
  std::optional<double> ended_unix_s;
  double distance_m = 0.0;
  GoalCounts goals;  // from the run's "goal" events whose detail ends a goal
};

// Runs: one per server process, with the trajectory and the events recorded while it lasted.
class RunStore {
 public:
  explicit RunStore(Database& database) : database_(database) {}

  std::int64_t start_run(const std::string& name, double started_unix_s);
  // Appends one batch in one transaction: all of it is stored, or none.
  void append(std::int64_t run_id, const std::vector<TrajectorySample>& samples,
              const std::vector<EventRecord>& events, double distance_m);
  void end_run(std::int64_t run_id, double ended_unix_s, double distance_m);
  // Closes runs a killed server left open, at their last recorded activity; returns how many.
  int close_dangling_runs(double now_unix_s);

  std::vector<RunRecord> list() const;
  std::optional<RunRecord> get(std::int64_t run_id) const;
  std::vector<TrajectorySample> trajectory(std::int64_t run_id) const;
  std::vector<EventRecord> events(std::int64_t run_id) const;

 private:
  Database& database_;
};

}  // namespace mobot::db
