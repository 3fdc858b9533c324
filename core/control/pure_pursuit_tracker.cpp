#include "core/control/pure_pursuit_tracker.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/numeric/finite.h"

namespace mobot::control {
namespace {

// Once backing up, it goes on until the goal is this far outside the turning circle, so the
// forward turn that follows does not bring it straight back in.
constexpr double kReverseMargin_m = 0.3;

}  // namespace

PurePursuitTracker::PurePursuitTracker(const PurePursuitOptions& options) : options_(options) {
  const PurePursuitOptions& o = options_;
  if (!finite_positive(o.lookahead_min_m) || !(o.lookahead_max_m >= o.lookahead_min_m) ||
      !(o.lookahead_time_s >= 0.0) || !finite_positive(o.max_linear_mps) ||
      !finite_positive(o.max_angular_radps) || !(o.min_turning_radius_m >= 0.0) ||
      !finite_positive(o.approach_decel_mps2) || !(o.min_linear_mps >= 0.0) ||
      !(o.min_linear_mps <= o.max_linear_mps) || !finite_positive(o.goal_tolerance_m) ||
      !finite_positive(o.goal_tolerance_rad) || !finite_positive(o.align_gain) ||
      !finite_positive(o.projection_window_m)) {
    throw std::invalid_argument(
        "pure pursuit: look-ahead min > 0 and <= max, speeds, tolerances and gains > 0, minimum "
        "speed within [0, max]");
  }
}

bool PurePursuitTracker::set_path(const planning::Path& path,
                                  std::optional<double> goal_heading_rad) {
  if (path.empty() || !path.all_finite() ||
      (goal_heading_rad && !std::isfinite(*goal_heading_rad))) {
    return false;
  }
  path_ = path;
  goal_heading_rad_ = goal_heading_rad;
  status_ = {};
  status_.state = TrackerState::kTracking;
  status_.remaining_m = path_.length_m();
  lookahead_.reset();
  reversing_ = false;
  return true;
}

void PurePursuitTracker::clear() {
  path_ = {};
  status_ = {};
  lookahead_.reset();
  reversing_ = false;
}

msgs::Twist PurePursuitTracker::compute(const geometry::Pose2D& pose, const msgs::Twist& velocity,
                                        double /*now_s*/) {
  if (status_.state == TrackerState::kIdle || status_.state == TrackerState::kArrived ||
      !geometry::is_finite(pose)) {
    return {};
  }
  status_.progress_m =
      path_.project({pose.x, pose.y}, status_.progress_m, options_.projection_window_m);
  status_.remaining_m = path_.length_m() - status_.progress_m;
  const geometry::Point2D goal = path_.back();
  status_.distance_to_goal_m = std::hypot(goal.x - pose.x, goal.y - pose.y);
  status_.heading_error_rad =
      goal_heading_rad_ ? geometry::wrap_angle(pose.theta - *goal_heading_rad_) : 0.0;
  if (status_.state == TrackerState::kTracking &&
      status_.distance_to_goal_m <= options_.goal_tolerance_m) {
    status_.state = TrackerState::kFinalApproach;
  }
  if (status_.state == TrackerState::kFinalApproach) return align(pose);
  return pursue(pose, velocity);
}

msgs::Twist PurePursuitTracker::pursue(const geometry::Pose2D& pose, const msgs::Twist& velocity) {
  const double lookahead_m = std::clamp(options_.lookahead_time_s * std::abs(velocity.linear_mps),
                                        options_.lookahead_min_m, options_.lookahead_max_m);
  lookahead_ = find_lookahead(path_, {pose.x, pose.y}, status_.progress_m, lookahead_m);
  double curvature = pursuit_curvature(pose, lookahead_->point);
  if (options_.min_turning_radius_m > 0.0) {
    const double max_curvature = 1.0 / options_.min_turning_radius_m;
    // The end of the path inside the turning circle cannot be reached going forward: back up
    // straight until it lies outside.
    // straight until it lies outside, with a margin so it does not pass the goal on the circle.
    // (Only near the end: a longer path may still lead round to the goal.)
    if (status_.remaining_m <= options_.lookahead_max_m + options_.min_turning_radius_m) {
      const double margin_m = reversing_ ? kReverseMargin_m : 0.0;
      reversing_ = inside_turning_circle(pose, path_.back(), margin_m);
      if (reversing_) return {-std::max(options_.min_linear_mps, 0.1), 0.0};
    }
    curvature = std::clamp(curvature, -max_curvature, max_curvature);
  }
  double speed_mps =
      std::min(options_.max_linear_mps,
               std::sqrt(2.0 * options_.approach_decel_mps2 * status_.distance_to_goal_m));
  if (std::abs(curvature) > 1e-9) {
    speed_mps = std::min(speed_mps, options_.max_angular_radps / std::abs(curvature));
  }
  speed_mps = std::max(speed_mps, options_.min_linear_mps);
  return {speed_mps, speed_mps * curvature};
}

msgs::Twist PurePursuitTracker::align(const geometry::Pose2D& /*pose*/) {
  if (!options_.align_heading || !goal_heading_rad_ ||
      std::abs(status_.heading_error_rad) <= options_.goal_tolerance_rad) {
    status_.state = TrackerState::kArrived;
    return {};
  }
  const double w = std::clamp(-options_.align_gain * status_.heading_error_rad,
                              -options_.max_angular_radps, options_.max_angular_radps);
  return {0.0, w};
}

bool PurePursuitTracker::inside_turning_circle(const geometry::Pose2D& pose,
                                               geometry::Point2D point, double margin_m) const {
  const double radius_m = options_.min_turning_radius_m;
  for (const double side : {1.0, -1.0}) {
    const geometry::Point2D centre{pose.x - side * std::sin(pose.theta) * radius_m,
                                   pose.y + side * std::cos(pose.theta) * radius_m};
    if (std::hypot(point.x - centre.x, point.y - centre.y) < radius_m + margin_m) return true;
  }
  return false;
}

}  // namespace mobot::control
