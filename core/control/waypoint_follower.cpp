#include "core/control/waypoint_follower.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/numeric/finite.h"

namespace mobot::control {
namespace {

LyapunovOptions carrot_options(const WaypointFollowerOptions& o) {
  LyapunovOptions out;
  out.gains = o.gains;
  out.two_law = false;  // the carrot keeps moving: never settle on it
  out.allow_reverse = false;
  out.max_linear_mps = o.max_linear_mps;
  out.max_angular_radps = o.max_angular_radps;
  return out;
}

LyapunovOptions goal_options(const WaypointFollowerOptions& o) {
  LyapunovOptions out;
  out.gains = o.gains;
  out.eps_rho_m = o.eps_rho_m;
  out.local_entry_max_lateral_m = o.local_entry_max_lateral_m;
  out.allow_reverse = o.allow_reverse_at_goal;
  out.max_linear_mps = o.max_linear_mps;
  out.max_angular_radps = o.max_angular_radps;
  return out;
}

std::vector<double> find_corners(const planning::Path& path, double min_turn_rad) {
  std::vector<double> corners;
  const auto& p = path.points();
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    const double in = std::atan2(p[i].y - p[i - 1].y, p[i].x - p[i - 1].x);
    const double out = std::atan2(p[i + 1].y - p[i].y, p[i + 1].x - p[i].x);
    if (std::abs(geometry::wrap_angle(out - in)) > min_turn_rad) {
      corners.push_back(path.s_at_vertex(i));
    }
  }
  return corners;
}

}  // namespace

WaypointFollower::WaypointFollower(const WaypointFollowerOptions& options)
    : options_(options),
      carrot_controller_(carrot_options(options)),
      goal_controller_(goal_options(options)) {
  if (!(options.lookahead_m > 0.0) || !finite_non_negative(options.final_approach_m) ||
      !finite_non_negative(options.goal_tolerance_m) ||
      !finite_non_negative(options.goal_tolerance_rad) ||
      !finite_non_negative(options.arrived_linear_mps) ||
      !finite_non_negative(options.arrived_angular_radps) || !(options.projection_window_m > 0.0) ||
      !std::isfinite(options.lookahead_m) || !std::isfinite(options.projection_window_m) ||
      !finite_non_negative(options.corner_angle_rad) ||
      !finite_non_negative(options.corner_switch_radius_m)) {
    throw std::invalid_argument("waypoint follower options out of range");
  }
}

bool WaypointFollower::set_path(const planning::Path& path,
                                std::optional<double> goal_heading_rad) {
  if (path.empty() || !path.all_finite()) return false;
  if (goal_heading_rad && !std::isfinite(*goal_heading_rad)) return false;
  path_ = path;
  corner_s_m_ = find_corners(path, options_.corner_angle_rad);
  next_corner_ = 0;
  const double heading = goal_heading_rad.value_or(path.heading_at(path.length_m()));
  goal_ = {path.back().x, path.back().y, geometry::wrap_angle(heading)};
  carrot_controller_.reset();
  goal_controller_.reset();
  status_ = {};
  status_.state = TrackerState::kTracking;
  status_.remaining_m = path.length_m();
  final_law_ = LyapunovLaw::kGlobal;
  return true;
}

void WaypointFollower::clear() {
  path_ = {};
  corner_s_m_.clear();
  next_corner_ = 0;
  status_ = {};
}

msgs::Twist WaypointFollower::compute(const geometry::Pose2D& pose, const msgs::Twist& velocity,
                                      double /*now_s*/) {
  if (status_.state == TrackerState::kIdle || status_.state == TrackerState::kArrived) return {};
  if (!geometry::is_finite(pose)) return {};

  status_.progress_m =
      path_.project({pose.x, pose.y}, status_.progress_m, options_.projection_window_m);
  status_.remaining_m = path_.length_m() - status_.progress_m;
  status_.distance_to_goal_m = std::hypot(goal_.x - pose.x, goal_.y - pose.y);
  status_.heading_error_rad = geometry::wrap_angle(pose.theta - goal_.theta);

  if (status_.state == TrackerState::kTracking &&
      (status_.remaining_m <= options_.final_approach_m ||
       status_.distance_to_goal_m <= options_.final_approach_m)) {
    status_.state = TrackerState::kFinalApproach;
  }
  return status_.state == TrackerState::kTracking ? track(pose) : approach(pose, velocity);
}

geometry::Pose2D WaypointFollower::carrot(const geometry::Pose2D& pose) {
  const double ahead_s = std::min(status_.progress_m + options_.lookahead_m, path_.length_m());
  while (next_corner_ < corner_s_m_.size()) {
    const double corner_s = corner_s_m_[next_corner_];
    const geometry::Point2D corner = path_.point_at(corner_s);
    const bool passed =
        corner_s <= status_.progress_m ||
        std::hypot(corner.x - pose.x, corner.y - pose.y) < options_.corner_switch_radius_m;
    if (!passed) {
      if (ahead_s < corner_s) break;
      // Held: aim along the segment that arrives at the corner.
      return {corner.x, corner.y, path_.heading_at(std::nextafter(corner_s, 0.0))};
    }
    ++next_corner_;
  }
  const geometry::Point2D point = path_.point_at(ahead_s);
  return {point.x, point.y, path_.heading_at(ahead_s)};
}

msgs::Twist WaypointFollower::track(const geometry::Pose2D& pose) {
  return carrot_controller_.compute(pose, carrot(pose)).command;
}

msgs::Twist WaypointFollower::approach(const geometry::Pose2D& pose, const msgs::Twist& velocity) {
  const bool in_tolerance = status_.distance_to_goal_m < options_.goal_tolerance_m &&
                            std::abs(status_.heading_error_rad) < options_.goal_tolerance_rad;
  const bool stopped = std::abs(velocity.linear_mps) < options_.arrived_linear_mps &&
                       std::abs(velocity.angular_radps) < options_.arrived_angular_radps;
  if (in_tolerance && stopped) {
    status_.state = TrackerState::kArrived;
    return {};
  }
  const LyapunovController::Output out = goal_controller_.compute(pose, goal_);
  final_law_ = out.law;
  return out.command;
}

}  // namespace mobot::control
