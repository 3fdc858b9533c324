#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace mobot::drivers {

// A device's own word on its health. A driver that cannot talk to its device (missing, silent,
// garbage) says so here; the runtime stops the robot when a required device is not ok.
struct DeviceStatus {
  bool ok = true;
  std::string reason;  // why not ok: "missing", "silent", "checksum", ...
};

// A real device's counters since the server started, for /metrics.
struct DeviceCounters {
  std::string name;  // "base", "laser", "ir", ...
  DeviceStatus status;
  std::uint64_t bytes = 0;            // received from the device
  std::uint64_t frames = 0;           // complete replies, packets or scans
  std::uint64_t checksum_errors = 0;  // frames that failed their checksum or did not parse
  std::uint64_t reconnects = 0;       // times the line was reopened after a failure
  std::optional<double> battery_v;    // a base that reports its battery
};

}  // namespace mobot::drivers
