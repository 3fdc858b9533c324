#include "core/control/pure_pursuit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace mobot::control {
namespace {

double distance(geometry::Point2D a, geometry::Point2D b) { return std::hypot(a.x - b.x, a.y - b.y); }

// The parameter t in [0, 1] where the segment a -> b leaves the circle about c (a inside it).
double exit_parameter(geometry::Point2D a, geometry::Point2D b, geometry::Point2D c,
                      double radius_m) {
  const double dx = b.x - a.x;
  const double dy = b.y - a.y;
  const double fx = a.x - c.x;
  const double fy = a.y - c.y;
  const double qa = dx * dx + dy * dy;
  const double qb = 2.0 * (fx * dx + fy * dy);
  const double qc = fx * fx + fy * fy - radius_m * radius_m;
  const double discriminant = std::max(0.0, qb * qb - 4.0 * qa * qc);
  return std::clamp((-qb + std::sqrt(discriminant)) / (2.0 * qa), 0.0, 1.0);
}

}  // namespace

LookaheadPoint find_lookahead(const planning::Path& path, geometry::Point2D robot,
                              double progress_m, double lookahead_m) {
  const geometry::Point2D start = path.point_at(progress_m);
  if (distance(start, robot) < lookahead_m) {
    // Walk from the projection to the first vertex outside the circle; the crossing lies on the
    // segment that leads to it.
    geometry::Point2D previous = start;
    double previous_s_m = progress_m;
    for (std::size_t i = 0; i < path.size(); ++i) {
      const double vertex_s_m = path.s_at_vertex(i);
      if (vertex_s_m <= progress_m) continue;
      const geometry::Point2D vertex = path.points()[i];
      if (distance(vertex, robot) >= lookahead_m) {
        const double t = exit_parameter(previous, vertex, robot, lookahead_m);
        return {{previous.x + t * (vertex.x - previous.x), previous.y + t * (vertex.y - previous.y)},
                previous_s_m + t * (vertex_s_m - previous_s_m),
                LookaheadSource::kCircle};
      }
      previous = vertex;
      previous_s_m = vertex_s_m;
    }
    return {path.back(), path.length_m(), LookaheadSource::kPathEnd};
  }
  // Off the path by more than the look-ahead: head for the nearest waypoint still ahead.
  LookaheadPoint nearest{path.back(), path.length_m(), LookaheadSource::kNearestWaypoint};
  double nearest_m = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (path.s_at_vertex(i) <= progress_m) continue;
    const double d = distance(path.points()[i], robot);
    if (d < nearest_m) {
      nearest_m = d;
      nearest = {path.points()[i], path.s_at_vertex(i), LookaheadSource::kNearestWaypoint};
    }
  }
  return nearest;
}

double pursuit_curvature(const geometry::Pose2D& pose, geometry::Point2D target) {
  const double dx = target.x - pose.x;
  const double dy = target.y - pose.y;
  const double distance_m = std::hypot(dx, dy);
  if (distance_m < 1e-9) return 0.0;
  const double eta = geometry::wrap_angle(std::atan2(dy, dx) - pose.theta);
  if (std::abs(eta) > std::numbers::pi / 2.0) return std::copysign(2.0 / distance_m, eta);
  return 2.0 * std::sin(eta) / distance_m;
}

}  // namespace mobot::control
