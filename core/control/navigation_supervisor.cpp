#include "core/control/navigation_supervisor.h"

#include <cmath>
#include <stdexcept>

#include "core/numeric/finite.h"

namespace mobot::control {

NavigationSupervisor::NavigationSupervisor(const NavigationSupervisorOptions& options,
                                           const PotentialFieldOptions& avoidance)
    : options_(options), detector_(avoidance) {
  if (!finite_non_negative(options.blocked_timeout_s) ||
      !finite_non_negative(options.min_progress_m) || !finite_non_negative(options.clear_hold_s) ||
      !finite_non_negative(options.rejoin_lookahead_m) || !(options.projection_window_m > 0.0) ||
      !std::isfinite(options.projection_window_m)) {
    throw std::invalid_argument("navigation supervisor options out of range");
  }
}

void NavigationSupervisor::set_path(const planning::Path& path, double now_s) {
  if (path.empty() || !path.all_finite()) {
    clear();
    return;
  }
  path_ = path;
  mode_ = NavigationMode::kTracking;
  progress_m_ = 0.0;
  best_progress_m_ = 0.0;
  last_progress_s_ = now_s;
  clear_since_s_.reset();
}

void NavigationSupervisor::clear() {
  path_ = {};
  mode_ = NavigationMode::kIdle;
  clear_since_s_.reset();
}

void NavigationSupervisor::note_progress(double now_s) {
  if (progress_m_ >= best_progress_m_ + options_.min_progress_m) {
    best_progress_m_ = progress_m_;
    last_progress_s_ = now_s;
  }
}

NavigationSupervisor::Decision NavigationSupervisor::update(
    double now_s, const geometry::Pose2D& pose, std::span<const msgs::RangeReading> sonar) {
  Decision decision;
  if (mode_ != NavigationMode::kIdle && geometry::is_finite(pose) && std::isfinite(now_s)) {
    progress_m_ = path_.project({pose.x, pose.y}, progress_m_, options_.projection_window_m);
    note_progress(now_s);
    const bool obstacle = detector_.is_active(sonar);
    switch (mode_) {
      case NavigationMode::kTracking:
        if (obstacle) {
          mode_ = NavigationMode::kAvoiding;
          decision.entered_avoidance = true;
          // The blocked timer measures progress made while avoiding, from now.
          best_progress_m_ = progress_m_;
          last_progress_s_ = now_s;
          clear_since_s_.reset();
        }
        break;
      case NavigationMode::kAvoiding:
        if (obstacle) {
          clear_since_s_.reset();
        } else if (!clear_since_s_) {
          clear_since_s_ = now_s;
        }
        if (clear_since_s_ && now_s - *clear_since_s_ >= options_.clear_hold_s) {
          mode_ = NavigationMode::kTracking;
          clear_since_s_.reset();
        } else if (now_s - last_progress_s_ >= options_.blocked_timeout_s) {
          mode_ = NavigationMode::kBlocked;
        }
        break;
      case NavigationMode::kIdle:
      case NavigationMode::kBlocked:
        break;
    }
  }
  decision.mode = mode_;
  decision.progress_m = progress_m_;
  if (!path_.empty()) {
    decision.rejoin_point = path_.point_at(progress_m_ + options_.rejoin_lookahead_m);
  }
  return decision;
}

}  // namespace mobot::control
