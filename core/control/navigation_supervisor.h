#pragma once

#include <optional>
#include <span>

#include "core/control/potential_field_avoider.h"
#include "core/geometry/pose2d.h"
#include "core/msgs/sonar_ring.h"
#include "core/planning/path.h"

namespace mobot::control {

enum class NavigationMode {
  kIdle,      // no path
  kTracking,  // the path tracker drives
  kAvoiding,  // an obstacle is within d0 ahead: the potential field drives toward rejoin_point
  kBlocked,   // avoidance made no progress along the path for blocked_timeout_s: replan
};

struct NavigationSupervisorOptions {
  // Avoidance that gains less than min_progress_m along the path within this long means the path
  // is blocked and the caller should replan.
  double blocked_timeout_s = 5.0;
  double min_progress_m = 0.2;
  // The sonar must stay clear this long before tracking resumes, so a flickering echo does not
  // toggle the controllers every tick.
  double clear_hold_s = 0.5;
  // The potential field is attracted to the path point this far ahead of the robot's projection,
  // so the robot rejoins the path beyond the obstacle instead of driving back to where it left it.
  double rejoin_lookahead_m = 1.5;
  double projection_window_m = 3.0;
};

// C4's navigation loop decision as a pure state machine (time is an argument): track the path,
// switch to avoidance when the sonar sees an obstacle within d0 in the sector ahead, switch back
// once clear, and report kBlocked, latched until the next path, when avoidance stops making
// progress along the path.
class NavigationSupervisor {
 public:
  struct Decision {
    NavigationMode mode = NavigationMode::kIdle;
    double progress_m = 0.0;         // arc length of the robot's projection onto the path
    geometry::Point2D rejoin_point;  // the avoider's goal while kAvoiding
    bool entered_avoidance = false;  // this tick switched to kAvoiding (reset the avoider)
  };

  // Throws std::invalid_argument on negative or non-finite options.
  NavigationSupervisor(const NavigationSupervisorOptions& options,
                       const PotentialFieldOptions& avoidance);

  // A new (re)planned path: back to kTracking with no history. An empty path means kIdle.
  void set_path(const planning::Path& path, double now_s);
  void clear();

  Decision update(double now_s, const geometry::Pose2D& pose,
                  std::span<const msgs::RangeReading> sonar);
  NavigationMode mode() const { return mode_; }

 private:
  void note_progress(double now_s);

  NavigationSupervisorOptions options_;
  PotentialFieldAvoider detector_;
  planning::Path path_;
  NavigationMode mode_ = NavigationMode::kIdle;
  double progress_m_ = 0.0;
  double best_progress_m_ = 0.0;
  double last_progress_s_ = 0.0;
  std::optional<double> clear_since_s_;
};

}  // namespace mobot::control
