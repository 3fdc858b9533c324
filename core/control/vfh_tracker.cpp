#include "core/control/vfh_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "core/numeric/constants.h"
#include "core/numeric/finite.h"

namespace mobot::control {
namespace {

using planning::PlanningGrid;

// The angle in [0, 2 pi).
double to_circle(double angle_rad) {
  const double a = std::fmod(angle_rad, kTwoPi);
  return a < 0.0 ? a + kTwoPi : a;
}

}  // namespace

VfhTracker::VfhTracker(const VfhOptions& options) : options_(options) {
  const VfhOptions& o = options;
  if (!valid(o.limits) || o.sector_count < 8 || o.sector_count > 360 ||
      !finite_positive(o.window_radius_m) ||
      !(o.unknown_certainty >= 0.0 && o.unknown_certainty <= 1.0) || o.smoothing_half_width < 0 ||
      o.smoothing_half_width > o.sector_count / 4 || !finite_positive(o.high_threshold) ||
      !finite_non_negative(o.low_threshold) || o.low_threshold > o.high_threshold ||
      o.wide_valley_sectors < 1 || o.wide_valley_sectors > o.sector_count ||
      o.min_valley_sectors < 1 || o.min_valley_sectors > o.sector_count ||
      !finite_non_negative(o.target_weight) || !finite_non_negative(o.heading_weight) ||
      !finite_non_negative(o.previous_weight) || !finite_positive(o.lookahead_m) ||
      !finite_positive(o.heading_gain) || !finite_positive(o.in_place_turn_rad) ||
      !finite_positive(o.slowdown_density) || !finite_positive(o.approach_time_s) ||
      !finite_positive(o.projection_window_m) || !finite_non_negative(o.goal_tolerance_m) ||
      !finite_non_negative(o.goal_tolerance_rad)) {
    throw std::invalid_argument("VFH tracker options out of range");
  }
  const auto n = static_cast<std::size_t>(o.sector_count);
  histogram_.assign(n, 0.0);
  smoothed_.assign(n, 0.0);
  binary_.assign(n, false);
}

bool VfhTracker::set_path(const planning::Path& path, std::optional<double> goal_heading_rad) {
  if (!progress_.start(path, goal_heading_rad)) return false;
  blocked_ = false;
  std::fill(binary_.begin(), binary_.end(), false);
  chosen_.reset();
  previous_.reset();
  return true;
}

void VfhTracker::clear() {
  progress_.clear();
  blocked_ = false;
  chosen_.reset();
  previous_.reset();
}

void VfhTracker::build_histogram(const geometry::Pose2D& pose) {
  const VfhOptions& o = options_;
  const auto n = static_cast<std::size_t>(o.sector_count);
  std::fill(histogram_.begin(), histogram_.end(), 0.0);
  const double sector_rad = kTwoPi / o.sector_count;
  if (costmap_ && !costmap_->empty()) {
    const PlanningGrid& grid = *costmap_;
    const double res = grid.resolution_m();
    // Magnitudes in units of a 0.1 m cell: the thresholds hold at any resolution.
    const double cell_weight = (res / 0.1) * (res / 0.1);
    const double radius = o.window_radius_m;
    const geometry::Point2D centre = grid.to_grid_frame_cells({pose.x, pose.y});
    const double r_cells = radius / res;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::max(-1.0, centre.x - r_cells))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::max(-1.0, centre.y - r_cells))));
    const int x1 = std::min(grid.width() - 1,
                            static_cast<int>(std::min(grid.width() + 1.0, centre.x + r_cells)));
    const int y1 = std::min(grid.height() - 1,
                            static_cast<int>(std::min(grid.height() + 1.0, centre.y + r_cells)));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const std::uint8_t cost = grid.cost({x, y});
        if (cost == PlanningGrid::kFree) continue;
        const double certainty =
            cost == PlanningGrid::kUnknown
                ? o.unknown_certainty
                : std::min<double>(cost, PlanningGrid::kInscribed) / PlanningGrid::kInscribed;
        if (certainty <= 0.0) continue;
        const geometry::Point2D c = grid.cell_center({x, y});
        const double dx = c.x - pose.x;
        const double dy = c.y - pose.y;
        const double d = std::hypot(dx, dy);
        if (d >= radius || d < 0.5 * res) continue;  // outside the window, or the robot's own cell
        const auto k =
            std::min(n - 1, static_cast<std::size_t>(to_circle(std::atan2(dy, dx)) / sector_rad));
        histogram_[k] += certainty * certainty * (radius - d) * cell_weight;
      }
    }
  }
  const int l = o.smoothing_half_width;
  const int sectors = o.sector_count;
  for (int k = 0; k < sectors; ++k) {
    double sum = 0.0;
    for (int i = -l; i <= l; ++i) {
      sum +=
          (l + 1 - std::abs(i)) * histogram_[static_cast<std::size_t>((k + i + sectors) % sectors)];
    }
    const auto ku = static_cast<std::size_t>(k);
    smoothed_[ku] = sum / (2 * l + 1);
    if (smoothed_[ku] > o.high_threshold) binary_[ku] = true;
    if (smoothed_[ku] < o.low_threshold) binary_[ku] = false;
  }
}

std::optional<double> VfhTracker::choose_direction(double target_rad, double heading_rad) const {
  const VfhOptions& o = options_;
  const int n = o.sector_count;
  const double sector_rad = kTwoPi / n;
  const auto blocked = [&](int k) { return binary_[static_cast<std::size_t>(((k % n) + n) % n)]; };
  int start = -1;
  for (int k = 0; k < n; ++k) {
    if (blocked(k)) {
      start = k;
      break;
    }
  }
  if (start < 0) return target_rad;  // nothing in the window: straight at the target
  // Candidates from every free valley, walking once round the circle from a blocked sector.
  std::vector<double> candidates;
  const auto direction_of = [sector_rad](double k) {
    return geometry::wrap_angle((k + 0.5) * sector_rad);
  };
  const auto angle_between = [](double a, double b) {
    return std::abs(geometry::wrap_angle(a - b));
  };
  for (int k = start + 1; k <= start + n; ++k) {
    if (blocked(k)) continue;
    const int first = k;  // right border (counter-clockwise order)
    while (k + 1 <= start + n && !blocked(k + 1)) ++k;
    const int last = k;  // left border
    const int width = last - first + 1;
    if (width < o.min_valley_sectors) continue;
    if (width < o.wide_valley_sectors) {
      candidates.push_back(direction_of(0.5 * (first + last)));
      continue;
    }
    const double half = 0.5 * o.wide_valley_sectors;
    const double right = direction_of(first + half - 0.5);
    const double left = direction_of(last - half + 0.5);
    candidates.push_back(right);
    candidates.push_back(left);
    // The target, when it lies between the two (counter-clockwise from right to left).
    const double span = to_circle(left - right);
    if (to_circle(target_rad - right) <= span) candidates.push_back(target_rad);
  }
  if (candidates.empty()) return std::nullopt;
  const double previous = previous_.value_or(heading_rad);
  double best_cost = std::numeric_limits<double>::infinity();
  double best = candidates.front();
  for (const double c : candidates) {
    const double cost = o.target_weight * angle_between(c, target_rad) +
                        o.heading_weight * angle_between(c, heading_rad) +
                        o.previous_weight * angle_between(c, previous);
    if (cost < best_cost) {
      best_cost = cost;
      best = c;
    }
  }
  return best;
}

msgs::Twist VfhTracker::compute(const geometry::Pose2D& pose, const msgs::Twist& velocity,
                                double /*now_s*/) {
  chosen_.reset();
  if (!progress_.update(pose, options_.goal_tolerance_m, options_.projection_window_m)) return {};
  if (progress_.tracking()) return track(pose, velocity);
  blocked_ = false;
  return progress_.final_approach(options_.limits, velocity, options_.goal_tolerance_rad);
}

msgs::Twist VfhTracker::track(const geometry::Pose2D& pose, const msgs::Twist& velocity) {
  const VfhOptions& o = options_;
  const DynamicLimits& limits = o.limits;
  // The target: the carrot on the path, or the goal itself once it is nearer than the carrot.
  const geometry::Point2D target =
      progress_.status().distance_to_goal_m <= o.lookahead_m
          ? geometry::Point2D{progress_.goal().x, progress_.goal().y}
          : progress_.path().point_at(std::min(progress_.status().progress_m + o.lookahead_m,
                                               progress_.path().length_m()));
  const double target_rad = std::atan2(target.y - pose.y, target.x - pose.x);

  build_histogram(pose);
  const std::optional<double> direction = choose_direction(target_rad, pose.theta);
  blocked_ = !direction.has_value();
  if (blocked_) return {};
  chosen_ = direction;
  previous_ = direction;

  const DynamicWindow window = reachable_window(limits, velocity);
  const double error = geometry::wrap_angle(*direction - pose.theta);
  msgs::Twist wanted;
  if (std::abs(error) > o.in_place_turn_rad) {
    const double rate = std::clamp(o.heading_gain * std::abs(error),
                                   limits.min_in_place_angular_radps, limits.max_angular_radps);
    wanted = {0.0, error > 0.0 ? rate : -rate};
  } else {
    wanted.angular_radps =
        std::clamp(o.heading_gain * error, -limits.max_angular_radps, limits.max_angular_radps);
    const double sector_rad = kTwoPi / o.sector_count;
    const auto ahead = std::min(static_cast<std::size_t>(o.sector_count - 1),
                                static_cast<std::size_t>(to_circle(pose.theta) / sector_rad));
    const double density = std::min(smoothed_[ahead], o.slowdown_density);
    wanted.linear_mps = limits.max_linear_mps * (1.0 - density / o.slowdown_density) *
                        (1.0 - std::abs(wanted.angular_radps) / limits.max_angular_radps);
    wanted.linear_mps =
        std::min(wanted.linear_mps, progress_.status().distance_to_goal_m / o.approach_time_s);
  }
  msgs::Twist command = window.clamp(wanted);
  // The last guard: where a short stretch of this motion ends must not be an inscribed cell.
  if (costmap_ && command.linear_mps > 0.0) {
    const double reach = std::max(command.linear_mps * 0.5, costmap_->resolution_m());
    const geometry::Point2D ahead{pose.x + reach * std::cos(pose.theta),
                                  pose.y + reach * std::sin(pose.theta)};
    const auto cell = costmap_->cell_at(ahead);
    if (cell && !PlanningGrid::is_traversable_cost(costmap_->cost(*cell))) {
      command.linear_mps = window.min_linear_mps;
    }
  }
  return command;
}

}  // namespace mobot::control
