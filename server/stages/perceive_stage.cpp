#include "server/stages/perceive_stage.h"

namespace mobot::server {

PerceiveStage::PerceiveStage(GridSource planning_grid, double blocking_distance_m)
    : planning_grid_(std::move(planning_grid)), blocking_distance_m_(blocking_distance_m) {}

void PerceiveStage::step(TickContext& context) {
  if (!context.scan && !context.sonar && !context.ir) return;
  obstacles_.set_map(planning_grid_());
  if (context.ir) {
    obstacles_.observe_ranges(context.ir->readings, context.pose, context.now_s);
    context.unmapped_points =
        std::make_shared<const std::vector<geometry::Point2D>>(obstacles_.points());
    context.scan_blocks_path =
        context.scan_blocks_path || obstacles_.blocks(context.active_path, blocking_distance_m_);
  }
  if (context.scan) {
    obstacles_.observe_scan(*context.scan,
                            geometry::compose(context.pose, context.scan->sensor_in_base));
    context.unmapped_points =
        std::make_shared<const std::vector<geometry::Point2D>>(obstacles_.points());
    context.scan_blocks_path =
        context.scan_blocks_path || obstacles_.blocks(context.active_path, blocking_distance_m_);
  }
  if (context.sonar) {
    // The sonar cones are coarse: they look 0.1 m wider than the laser blocks.
    context.avoidance_echoes = obstacles_.echoes_on_path(
        *context.sonar, context.pose, context.active_path, blocking_distance_m_ + 0.1);
  }
}

}  // namespace mobot::server
