#pragma once

#include "api/ports/domain_error.h"

namespace mobot::server {

// The refusals more than one service gives, worded once.
inline api::DomainError estop_engaged() {
  return {api::ErrorKind::kConflict, "estop_engaged", "e-stop is engaged: release it first"};
}

inline api::DomainError mapping_active() {
  return {api::ErrorKind::kConflict, "mapping_active",
          "a map is being built: stop mapping first (POST /api/v1/mapping)"};
}

}  // namespace mobot::server
