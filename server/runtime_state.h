#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "api/ports/control_port.h"
#include "api/ports/sim_control_port.h"
#include "core/navigation/goal.h"
#include "server/tick_context.h"

namespace mobot::server {

// What the network reads: the robot as of the end of the last tick or command, immutable once
// published, so a reader never waits on the control loop.
struct RuntimeState {
  api::RobotSnapshot robot;
  std::shared_ptr<const std::vector<navigation::Goal>> goals;
  std::optional<SweepProgress> sweep;
  std::optional<api::SimTruth> truth;
  double distance_m = 0.0;
  api::TrackingSnapshot target;
};

}  // namespace mobot::server
