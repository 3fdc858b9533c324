#pragma once

#include <memory>
#include <string_view>
#include <vector>

#include "core/control/path_tracker.h"
#include "core/control/waypoint_follower.h"

namespace mobot::control {

// Options of every tracker the factory can make; each reads its own part.
struct PathTrackerOptions {
  WaypointFollowerOptions lyapunov;
};

// The tracker registered under `name` (CONTRACT.md's "controller" field), or nullptr when no
// tracker has that name yet.
std::unique_ptr<PathTracker> make_path_tracker(std::string_view name,
                                               const PathTrackerOptions& options = {});

std::vector<std::string_view> path_tracker_names();

}  // namespace mobot::control
