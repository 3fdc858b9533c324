#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "api/ports/result.h"
#include "core/mapping/occupancy_grid.h"
#include "core/perception/point_cloud.h"

namespace mobot::api {

struct SweepRequest {
  double period_s = 10.0;  // 10 | 42
  double step_deg = 1.0;   // 1 | 0.5 | 0.25
};

struct SweepInfo {
  std::int64_t id = 0;
  std::string status;  // running | done | failed
  std::string reason;  // why it failed
  double period_s = 0.0;
  double step_deg = 0.0;
  int scans = 0;
  int scans_done = 0;
  std::int64_t points = 0;
  double started_t = 0.0;
  std::optional<double> ended_t;
};

// 3D sweeps of the tilting laser and their IPaBD obstacle maps. Thread-safe; the methods that
// answer at once throw DomainException.
class SweepsPort {
 public:
  virtual ~SweepsPort() = default;

  // kInvalid invalid_mode (not a sweep mode of the tilt unit), kConflict sweep_running.
  virtual void start_sweep(const SweepRequest& request, Completion<SweepInfo> done) = 0;
  virtual std::vector<SweepInfo> list_sweeps() const = 0;
  virtual std::optional<SweepInfo> find_sweep(std::int64_t id) const = 0;
  // kNotFound unknown_sweep, kConflict sweep_not_done (running or failed).
  virtual perception::PointCloud sweep_cloud(std::int64_t id) const = 0;
  virtual mapping::OccupancyGrid sweep_obstacle_map(std::int64_t id) const = 0;
  // Deletes a finished sweep's record, cloud and map (the 3D layer keeps what it merged).
  // kNotFound unknown_sweep, kConflict sweep_running.
  virtual void delete_sweep(std::int64_t id) = 0;
};

}  // namespace mobot::api
