#pragma once

#include <optional>

#include "core/geometry/pose2d.h"
#include "core/planning/path.h"

namespace mobot::control {

// Where the pure-pursuit look-ahead point came from.
enum class LookaheadSource {
  kCircle,            // the path crosses the look-ahead circle ahead of the robot
  kNearestWaypoint,   // the robot is off the path: no crossing; the nearest waypoint ahead
  kPathEnd,           // the rest of the path lies inside the circle: its end
};

struct LookaheadPoint {
  geometry::Point2D point;
  double s_m = 0.0;  // the arc length at the point
  LookaheadSource source = LookaheadSource::kCircle;
};

// The look-ahead point of docs/algorithms.md C3: the first crossing of the circle of radius
// lookahead_m about the robot with the path beyond the robot's projection progress_m. The source
// crashed when there was no crossing; here the fallbacks are the path's end when the rest lies
// inside the circle and the nearest remaining waypoint when the robot is off the path. The path
// must not be empty.
LookaheadPoint find_lookahead(const planning::Path& path, geometry::Point2D robot,
                              double progress_m, double lookahead_m);

// C3's curvature towards a point: k = 2 sin(eta) / L_d with eta the point's bearing from the
// heading and L_d its distance. A point behind the robot (|eta| > pi/2) asks for the tightest
// turn towards it, 2 / L_d, instead of the small curvature sin(eta) gives there.
double pursuit_curvature(const geometry::Pose2D& pose, geometry::Point2D target);

}  // namespace mobot::control
