#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "core/perception/point_cloud.h"
#include "core/perception/tilt_sweep.h"
#include "drivers/tilt_laser_driver.h"
#include "server/map_listener.h"
#include "server/stage.h"

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

// One sweep of the nodding laser at a time (docs/algorithms.md R1, P1): each scan the tilt
// driver yields goes into the map frame with the pose the robot believes it has and out on the
// `cloud` topic; the whole cloud goes to the listener when the last scan is in, or the reason
// when the sweep ends early (a reset, a map change). The listener runs on the control loop and
// must only hand the outcome on.
class SweepStage final : public Stage, public MapListener {
 public:
  using Listener = std::function<void(SweepOutcome)>;

  SweepStage(drivers::TiltLaserDriver& tilt, Listener listener);

  std::string_view name() const override { return "sweep"; }
  void step(TickContext& context) override;

  // false while a sweep runs.
  bool start(std::int64_t id, const perception::SweepMode& mode, TickContext& context);
  void abort(const std::string& reason, TickContext& context);

  void prepare_map(const ActiveMap&) override {}
  void apply_map(const ActiveMap& map, TickContext& context) override;

 private:
  void take_scan(const msgs::TiltScan& scan, TickContext& context);
  void finish(std::optional<std::string> failure, TickContext& context);

  struct Active {
    std::int64_t id = 0;
    perception::SweepMode mode;
    double started_s = 0.0;
    int scans_done = 0;
    geometry::Point2D origin_in_map;
    perception::PointCloud cloud;
  };
  drivers::TiltLaserDriver& tilt_;
  Listener listener_;
  std::optional<Active> sweep_;
  std::uint64_t map_generation_ = 0;
};

}  // namespace mobot::server
