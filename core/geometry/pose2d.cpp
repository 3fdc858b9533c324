#include "core/geometry/pose2d.h"

#include <cmath>
#include <numbers>

namespace mobot::geometry {

double wrap_angle(double angle_rad) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  double wrapped = std::fmod(angle_rad + std::numbers::pi, kTwoPi);
  if (wrapped <= 0.0) wrapped += kTwoPi;
  return wrapped - std::numbers::pi;
}

Pose2D compose(const Pose2D& a, const Pose2D& b) {
  const double c = std::cos(a.theta);
  const double s = std::sin(a.theta);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, wrap_angle(a.theta + b.theta)};
}

Pose2D inverse(const Pose2D& a) {
  const double c = std::cos(a.theta);
  const double s = std::sin(a.theta);
  return {-c * a.x - s * a.y, s * a.x - c * a.y, wrap_angle(-a.theta)};
}

Point2D transform_point(const Pose2D& frame, const Point2D& point) {
  const double c = std::cos(frame.theta);
  const double s = std::sin(frame.theta);
  return {frame.x + c * point.x - s * point.y, frame.y + s * point.x + c * point.y};
}

bool is_finite(const Pose2D& pose) {
  return std::isfinite(pose.x) && std::isfinite(pose.y) && std::isfinite(pose.theta);
}

double distance_m(const Point2D& a, const Point2D& b) { return std::hypot(a.x - b.x, a.y - b.y); }

}  // namespace mobot::geometry
