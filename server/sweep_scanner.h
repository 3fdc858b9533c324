#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "api/stream_hub.h"
#include "core/geometry/pose2d.h"
#include "core/perception/point_cloud.h"
#include "core/perception/tilt_sweep.h"
#include "drivers/sim/simulator.h"
#include "drivers/sim/tilt_motion.h"

namespace mobot::server {

// How a sweep ended on the robot: its cloud, or why it has none.
struct SweepOutcome {
  std::int64_t id = 0;
  std::optional<std::string> failure;
  perception::PointCloud cloud;
  geometry::Point2D origin_in_map;  // where the tilt axis stood at the first scan
  double started_s = 0.0;
  double ended_s = 0.0;
  // The active map's generation when the sweep ended: its cells belong on that map only.
  std::uint64_t map_generation = 0;
};

struct SweepProgress {
  std::int64_t id = 0;
  int scans_done = 0;
  int scans = 0;
  std::size_t points = 0;
};

// Runs one sweep of the nodding laser on the control loop (R1, P1): at every scan time of the
// mode it reads a scan at the tilt unit's true pitch, assigns it the pitch its count implies,
// puts its points in the map frame with the pose the robot believes it has, and publishes them
// on the `cloud` topic. Not thread-safe: the Robot calls it under its mutex.
class SweepScanner {
 public:
  bool running() const { return sweep_.has_value(); }
  std::optional<SweepProgress> progress() const;

  // The first scan is taken by the next tick(). `seed` varies the tilt unit's ripple phase.
  void start(std::int64_t id, const perception::SweepMode& mode, double now_s,
             const sim::RobotProfile& profile, std::uint64_t seed);
  // Takes the scans that are due; the outcome once the last is taken.
  std::optional<SweepOutcome> tick(sim::Simulator& sim, const geometry::Pose2D& base_in_map,
                                   double now_s, api::StreamHub& hub);
  // Ends a running sweep without a cloud.
  std::optional<SweepOutcome> abort(const std::string& reason, double now_s);

 private:
  struct Active {
    std::int64_t id = 0;
    perception::SweepMode mode;
    perception::TiltRange range;
    sim::TiltMotion motion;
    double started_s = 0.0;
    int scans_done = 0;
    geometry::Point2D origin_in_map;
    perception::PointCloud cloud;
  };
  std::optional<Active> sweep_;
};

}  // namespace mobot::server
