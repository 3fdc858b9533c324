#include "server/stages/costmap_stage.h"

#include "core/costmap/inflation_layer.h"

namespace mobot::server {
namespace {

costmap::RangeSensorLayerOptions named(costmap::RangeSensorLayerOptions options, const char* name) {
  options.name = name;
  return options;
}

}  // namespace

CostmapStage::CostmapStage(const CostmapStageOptions& options, GlobalCostmap global)
    : costmap_(options.window),
      global_(std::move(global)),
      local_schedule_(options.local_publish_period_s),
      global_schedule_(options.global_publish_period_s) {
  laser_ = &costmap_.add(std::make_unique<costmap::ObstacleLayer>(options.laser));
  sonar_ =
      &costmap_.add(std::make_unique<costmap::RangeSensorLayer>(named(options.sonar, "sonar")));
  ir_ = &costmap_.add(std::make_unique<costmap::RangeSensorLayer>(named(options.ir, "ir")));
  costmap::InflationLayerOptions inflation;
  inflation.inscribed_radius_m = options.inscribed_radius_m;
  inflation.inflation_radius_m = options.inscribed_radius_m + options.inflation_radius_m;
  inflation.cost_scaling_per_m = options.cost_scaling_per_m;
  costmap_.add(std::make_unique<costmap::InflationLayer>(inflation));
}

void CostmapStage::step(TickContext& context) {
  bool observed = false;
  if (context.scan) {
    observed |= laser_->add_scan(*context.scan,
                                 geometry::compose(context.pose, context.scan->sensor_in_base));
  }
  if (context.sonar) observed |= sonar_->add_readings(context.sonar->readings, context.pose);
  if (context.ir) observed |= ir_->add_readings(context.ir->readings, context.pose);
  if (observed || !context.local_costmap) {
    costmap_.update(context.pose);
    context.local_costmap = costmap_.snapshot();
  }
  if (local_schedule_.due(context.now_s) && context.local_costmap &&
      !context.local_costmap->empty()) {
    local_schedule_.taken(context.now_s);
    context.bus->costmap.publish({context.now_s, context.local_costmap, true});
  }
  if (global_schedule_.due(context.now_s)) {
    global_schedule_.taken(context.now_s);
    if (auto global = global_())
      context.bus->costmap.publish({context.now_s, std::move(global), false});
  }
}

}  // namespace mobot::server
