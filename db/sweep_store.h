#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/mapping/occupancy_grid.h"
#include "core/perception/point_cloud.h"
#include "db/database.h"

namespace mobot::db {

struct SweepRecord {
  std::int64_t id = 0;
  std::string status;  // "running", "done" or "failed"
  std::string reason;  // why it failed; empty otherwise
  double period_s = 0.0;
  double step_deg = 0.0;
  int scans = 0;
  double started_t = 0.0;  // robot clock
  std::optional<double> ended_t;
  std::int64_t points = 0;
};

// 3D sweeps: a row is written when the sweep is accepted, so an acknowledged sweep is never lost;
// its cloud and IPaBD map arrive in the transaction that marks it done.
class SweepStore {
 public:
  explicit SweepStore(Database& database) : database_(database) {}

  std::int64_t insert_running(double period_s, double step_deg, int scans, double started_t,
                              double created_unix_s, std::optional<std::int64_t> run_id);
  // False when the sweep is unknown or not running (nothing changed).
  bool finish(std::int64_t id, double ended_t, const perception::PointCloud& cloud,
              const mapping::OccupancyGrid& obstacle_map);
  bool fail(std::int64_t id, double ended_t, const std::string& reason);
  // Sweeps a previous process left running can never finish: marks them failed. Returns how many.
  int fail_interrupted(const std::string& reason);
  enum class RemoveResult { kRemoved, kNotFound, kRunning };
  // Deletes a sweep that is done or failed, with its cloud and map.
  RemoveResult remove(std::int64_t id);

  std::vector<SweepRecord> list() const;
  std::optional<SweepRecord> get(std::int64_t id) const;
  // Only for a done sweep.
  std::optional<perception::PointCloud> cloud(std::int64_t id) const;
  std::optional<mapping::OccupancyGrid> obstacle_map(std::int64_t id) const;

 private:
  Database& database_;
};

}  // namespace mobot::db
