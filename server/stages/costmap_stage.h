#pragma once

#include <functional>
#include <memory>

#include "core/costmap/layered_costmap.h"
#include "core/costmap/obstacle_layer.h"
#include "core/costmap/range_sensor_layer.h"
#include "core/planning/planning_grid.h"
#include "core/timing/rate_schedule.h"
#include "server/stage.h"

namespace mobot::server {

struct CostmapStageOptions {
  // docs/algorithms.md P3: the Dashgo's local costmap, 3 x 3 m at 0.05 m.
  costmap::LayeredCostmapOptions window{true, 3.0, 3.0, 0.05, {}, false};
  costmap::ObstacleLayerOptions laser;
  costmap::RangeSensorLayerOptions sonar;
  costmap::RangeSensorLayerOptions ir;
  double inscribed_radius_m = 0.3;
  double inflation_radius_m = 0.25;  // beyond the inscribed radius
  double cost_scaling_per_m = 10.0;
  double local_publish_period_s = 0.2;   // local_costmap at 5 Hz
  double global_publish_period_s = 2.0;  // costmap (the planning grid) for late subscribers
};

// The rolling local costmap around the robot (docs/algorithms.md P3): the laser's obstacle layer
// with ray-traced clearing, the sonar and IR rings each in a layer of its own (a table top only the
// IR ring sees is never cleared by the laser), and inflation. The trackers steer on it (DWA, VFH);
// the `local_costmap` and `costmap` topics show it and the planning grid.
class CostmapStage final : public Stage {
 public:
  using GlobalCostmap = std::function<std::shared_ptr<const planning::PlanningGrid>()>;

  CostmapStage(const CostmapStageOptions& options, GlobalCostmap global);

  std::string_view name() const override { return "costmap"; }
  void step(TickContext& context) override;

  const planning::PlanningGrid& local() const { return costmap_.master(); }

 private:
  costmap::LayeredCostmap costmap_;
  costmap::ObstacleLayer* laser_ = nullptr;
  costmap::RangeSensorLayer* sonar_ = nullptr;
  costmap::RangeSensorLayer* ir_ = nullptr;
  GlobalCostmap global_;
  timing::RateSchedule local_schedule_;
  timing::RateSchedule global_schedule_;
};

}  // namespace mobot::server
