#pragma once

#include <string>

#include "core/kinematics/robot_geometry.h"

#include "core/timing/rate_schedule.h"
#include "server/stage.h"

namespace mobot::server {

// What /robot says of the machine itself: its kinematic model's name and its dimensions.
struct RobotDescription {
  std::string kinematics;
  kinematics::RobotGeometry geometry;
};

// The tick's results on the bus: pose and odometry every tick, the scan and the sonar ring when
// new, the status at 1 Hz; then the end of the batch, for the subscribers to send it.
class PublishStage final : public Stage {
 public:
  explicit PublishStage(RobotDescription robot) : robot_(std::move(robot)) {}

  std::string_view name() const override { return "publish"; }
  void step(TickContext& context) override;
  // The laser's scans reach the stream on their own (ScanForwarder): the tick publishes none.
  void leave_scans_to_forwarder() { scans_forwarded_ = true; }

 private:
  bool scans_forwarded_ = false;
  const RobotDescription robot_;
  timing::RateSchedule status_schedule_{1.0};
};

// /robot's body as the context has it now.
api::RobotSnapshot robot_snapshot(const TickContext& context, const RobotDescription& robot);

}  // namespace mobot::server
