#pragma once

#include "core/msgs/laser_scan.h"
#include "server/bus.h"
#include "server/runtime.h"

namespace mobot::server {

// A real laser's scans straight to the stream, on the laser's thread, the moment a scan is
// complete: through the control tick a scan waited up to one period (20 ms at 50 Hz, 11 ms on
// average) for the next poll. Each scan is placed with the newest published pose and stamped
// with its robot time; the tick still reads the same scan for localization and mapping.
class ScanForwarder {
 public:
  ScanForwarder(Bus& bus, const Runtime& runtime) : bus_(bus), runtime_(runtime) {}

  void operator()(const msgs::LaserScan& scan) const;

 private:
  Bus& bus_;
  const Runtime& runtime_;
};

}  // namespace mobot::server
