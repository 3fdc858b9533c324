#pragma once

#include <string>

#include "core/timing/rate_schedule.h"
#include "server/stage.h"

namespace mobot::server {

// The tick's results on the bus: pose and odometry every tick, the scan and the sonar ring when
// new, the status at 1 Hz; then the end of the batch, for the subscribers to send it.
class PublishStage final : public Stage {
 public:
  explicit PublishStage(std::string kinematics) : kinematics_(std::move(kinematics)) {}

  std::string_view name() const override { return "publish"; }
  void step(TickContext& context) override;
  // The laser's scans reach the stream on their own (ScanForwarder): the tick publishes none.
  void leave_scans_to_forwarder() { scans_forwarded_ = true; }

 private:
  bool scans_forwarded_ = false;
  const std::string kinematics_;
  timing::RateSchedule status_schedule_{1.0};
};

// /robot's body as the context has it now.
api::RobotSnapshot robot_snapshot(const TickContext& context, const std::string& kinematics);

}  // namespace mobot::server
