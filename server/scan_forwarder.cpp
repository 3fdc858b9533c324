#include "server/scan_forwarder.h"

namespace mobot::server {

void ScanForwarder::operator()(const msgs::LaserScan& scan) const {
  const std::shared_ptr<const RuntimeState> state = runtime_.state();
  if (!state) return;
  msgs::LaserScan stamped = scan;
  stamped.stamp_s = state->robot.t_s;
  // The scan topic's subscriber (the stream hub) and the flush are safe from any thread.
  bus_.scan.publish({stamped, geometry::compose(state->robot.pose, scan.sensor_in_base)});
  bus_.flush.publish({});
}

}  // namespace mobot::server
