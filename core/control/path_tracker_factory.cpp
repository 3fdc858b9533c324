#include "core/control/path_tracker_factory.h"

namespace mobot::control {

std::unique_ptr<PathTracker> make_path_tracker(std::string_view name,
                                               const PathTrackerOptions& options) {
  if (name == "lyapunov") return std::make_unique<WaypointFollower>(options.lyapunov);
  return nullptr;
}

std::vector<std::string_view> path_tracker_names() { return {"lyapunov"}; }

}  // namespace mobot::control
