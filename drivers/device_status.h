#pragma once

#include <string>

namespace mobot::drivers {

// A device's own word on its health. A driver that cannot talk to its device (missing, silent,
// garbage) says so here; the runtime stops the robot when a required device is not ok.
struct DeviceStatus {
  bool ok = true;
  std::string reason;  // why not ok: "missing", "silent", "checksum", ...
};

}  // namespace mobot::drivers
