#include "core/control/dwa_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/control/stop_and_rotate.h"
#include "core/geometry/polyline.h"
#include "core/numeric/finite.h"
#include "core/numeric/step_toward.h"

namespace mobot::control {
namespace {

using planning::PlanningGrid;

// Costs of map-frame points on the local costmap, with the grid's inverse transform computed once.
// Points off the costmap (or no costmap) cost nothing: nothing is known to block them.
class CostLookup {
 public:
  explicit CostLookup(const PlanningGrid* grid) : grid_(grid) {
    if (grid_ == nullptr || grid_->empty()) {
      grid_ = nullptr;
      return;
    }
    c_ = std::cos(grid_->origin().theta);
    s_ = std::sin(grid_->origin().theta);
    inv_res_ = 1.0 / grid_->resolution_m();
  }
  bool has_grid() const { return grid_ != nullptr; }
  std::optional<mapping::CellIndex> cell(double x, double y) const {
    if (grid_ == nullptr) return std::nullopt;
    const double dx = x - grid_->origin().x;
    const double dy = y - grid_->origin().y;
    const double gx = (c_ * dx + s_ * dy) * inv_res_;
    const double gy = (-s_ * dx + c_ * dy) * inv_res_;
    if (!(gx >= 0.0 && gy >= 0.0 && gx < grid_->width() && gy < grid_->height())) {
      return std::nullopt;
    }
    return mapping::CellIndex{static_cast<int>(gx), static_cast<int>(gy)};
  }
  std::uint8_t cost(double x, double y) const {
    const auto c = cell(x, y);
    return c ? grid_->cost(*c) : PlanningGrid::kFree;
  }

 private:
  const PlanningGrid* grid_ = nullptr;
  double c_ = 1.0;
  double s_ = 0.0;
  double inv_res_ = 1.0;
};

// `count` values spread evenly over [lo, hi], both ends included, plus zero when the range holds
// it (base_local_planner's VelocityIterator).
std::vector<double> samples(double lo, double hi, int count) {
  std::vector<double> out;
  if (hi - lo < 1e-9 || count <= 1) {
    out.push_back(count <= 1 ? 0.5 * (lo + hi) : hi);
  } else {
    for (int i = 0; i < count; ++i) out.push_back(lo + (hi - lo) * i / (count - 1));
  }
  if (lo <= 0.0 && hi >= 0.0 &&
      std::none_of(out.begin(), out.end(), [](double v) { return v == 0.0; })) {
    out.push_back(0.0);
  }
  return out;
}

// Calls visit(pose) for the poses after 1..steps steps of dt at constant (v, w) from `start`, on
// the exact arc, until visit returns false. The heading's sine and cosine advance by a rotation
// per step (no trigonometry inside the loop).
template <class Visit>
void roll_out(const geometry::Pose2D& start, double v, double w, int steps, double dt,
              Visit&& visit) {
  const double turn = w * dt;
  const double cos_turn = std::cos(turn);
  const double sin_turn = std::sin(turn);
  double c = std::cos(start.theta);
  double s = std::sin(start.theta);
  geometry::Pose2D pose = start;
  const bool straight = std::abs(w) < 1e-9;
  const double radius = straight ? 0.0 : v / w;
  for (int i = 1; i <= steps; ++i) {
    const double next_c = c * cos_turn - s * sin_turn;
    const double next_s = s * cos_turn + c * sin_turn;
    if (straight) {
      pose.x += v * dt * c;
      pose.y += v * dt * s;
    } else {
      pose.x += radius * (next_s - s);
      pose.y -= radius * (next_c - c);
    }
    pose.theta = start.theta + turn * i;
    c = next_c;
    s = next_s;
    if (!visit(pose)) return;
  }
}

// roll_out for Trajectory Rollout: from the velocity `from`, each step first moves the velocity
// toward `to` by the accelerations' reach in dt, then follows that step's arc.
template <class Visit>
void roll_out_accelerating(const geometry::Pose2D& start, const msgs::Twist& from,
                           const msgs::Twist& to, const DynamicLimits& limits, int steps, double dt,
                           Visit&& visit) {
  geometry::Pose2D pose = start;
  double v = from.linear_mps;
  double w = from.angular_radps;
  for (int i = 1; i <= steps; ++i) {
    v = step_toward(v, to.linear_mps, limits.linear_accel_mps2 * dt);
    w = step_toward(w, to.angular_radps, limits.angular_accel_radps2 * dt);
    const double turn = w * dt;
    if (std::abs(w) < 1e-9) {
      pose.x += v * dt * std::cos(pose.theta);
      pose.y += v * dt * std::sin(pose.theta);
    } else {
      const double radius = v / w;
      pose.x += radius * (std::sin(pose.theta + turn) - std::sin(pose.theta));
      pose.y -= radius * (std::cos(pose.theta + turn) - std::cos(pose.theta));
    }
    pose.theta += turn;
    if (!visit(pose)) return;
  }
}

}  // namespace

// What a trajectory is scored against this tick.
struct DwaTracker::Scoring {
  // The local path without the stretches over lethal cells (ROS drops path cells inside obstacles
  // from its path map), so going round an obstacle on the path is not scored as leaving the path
  // there. Inscribed cells stay: a path along the edge of an inscribed zone is still the path.
  std::vector<std::vector<geometry::Point2D>> free_path;
  geometry::Point2D local_goal;
  geometry::Point2D goal_front;  // the local goal pushed forward_point_distance_m along the path
  double alignment_scale = 0.0;  // path_distance_bias, or 0 near the goal
  double path_distance(geometry::Point2D p) const {
    double best = free_path.empty() ? 0.0 : std::numeric_limits<double>::infinity();
    for (const auto& piece : free_path) {
      best = std::min(best, piece.size() == 1 ? planning::distance(piece.front(), p)
                                              : geometry::distance_to_polyline(piece, p));
    }
    return best;
  }
  double score(const DwaOptions& o, const geometry::Pose2D& end, std::uint8_t max_cost) const {
    const geometry::Point2D end_point{end.x, end.y};
    const geometry::Point2D nose{end.x + o.forward_point_distance_m * std::cos(end.theta),
                                 end.y + o.forward_point_distance_m * std::sin(end.theta)};
    const double to_goal = planning::distance(end_point, local_goal);
    const double nose_to_front = planning::distance(nose, goal_front);
    return o.path_distance_bias * path_distance(end_point) + o.goal_distance_bias * to_goal +
           alignment_scale * path_distance(nose) + o.goal_distance_bias * nose_to_front +
           o.occdist_scale * max_cost;
  }
};

DwaTracker::DwaTracker(const DwaOptions& options) : options_(options) {
  const DwaOptions& o = options;
  if (!valid(o.limits) || !finite_positive(o.sim_time_s) || !finite_positive(o.sim_granularity_m) ||
      !finite_positive(o.angular_sim_granularity_rad) || o.linear_samples < 1 ||
      o.linear_samples > 100 || o.angular_samples < 1 || o.angular_samples > 100 ||
      !finite_non_negative(o.path_distance_bias) || !finite_non_negative(o.goal_distance_bias) ||
      !finite_non_negative(o.occdist_scale) || !finite_non_negative(o.forward_point_distance_m) ||
      !finite_positive(o.local_goal_distance_m) || !finite_positive(o.projection_window_m) ||
      !finite_non_negative(o.min_improvement) || !finite_non_negative(o.goal_tolerance_m) ||
      !finite_non_negative(o.goal_tolerance_rad) || !finite_non_negative(o.approach_radius_m)) {
    throw std::invalid_argument("DWA tracker options out of range");
  }
}

bool DwaTracker::set_path(const planning::Path& path, std::optional<double> goal_heading_rad) {
  if (!progress_.start(path, goal_heading_rad)) return false;
  blocked_ = false;
  chosen_.clear();
  return true;
}

void DwaTracker::clear() {
  progress_.clear();
  blocked_ = false;
  chosen_.clear();
}

msgs::Twist DwaTracker::compute(const geometry::Pose2D& pose, const msgs::Twist& velocity,
                                double /*now_s*/) {
  scored_ = 0;
  admissible_ = 0;
  chosen_.clear();
  if (!progress_.update(pose, options_.goal_tolerance_m, options_.projection_window_m)) return {};
  if (progress_.tracking()) return track(pose, velocity);
  blocked_ = false;
  return progress_.final_approach(options_.limits, velocity, options_.goal_tolerance_rad);
}

msgs::Twist DwaTracker::track(const geometry::Pose2D& pose, const msgs::Twist& velocity) {
  const planning::Path& path = progress_.path();
  const DwaOptions& o = options_;
  const CostLookup costs(costmap_.get());

  // The local goal: where the path leaves the costmap, or local_goal_distance_m along it.
  const double from_s = progress_.status().progress_m;
  double goal_s = std::min(from_s + o.local_goal_distance_m, path.length_m());
  if (costs.has_grid()) {
    const double step = costmap_->resolution_m();
    goal_s = from_s;
    for (double s = from_s; s <= path.length_m(); s += step) {
      const geometry::Point2D p = path.point_at(s);
      if (!costs.cell(p.x, p.y)) break;
      goal_s = s;
    }
    const geometry::Point2D end = path.back();
    if (costs.cell(end.x, end.y) && goal_s + step > path.length_m()) goal_s = path.length_m();
  }
  Scoring scoring;
  // The path from the projection to the local goal, sampled at the costmap's resolution, split
  // where it crosses lethal cells.
  const double sample_m = costs.has_grid() ? costmap_->resolution_m() : o.local_goal_distance_m;
  // The polyline of the path between two arc lengths: its ends and the path's own vertices
  // between them (a straight stretch stays two points however finely it was sampled).
  const auto stretch = [&path](double begin_s, double end_s) {
    std::vector<geometry::Point2D> out{path.point_at(begin_s)};
    for (std::size_t i = 0; i < path.size(); ++i) {
      if (path.s_at_vertex(i) > begin_s && path.s_at_vertex(i) < end_s) {
        out.push_back(path.points()[i]);
      }
    }
    if (end_s > begin_s) out.push_back(path.point_at(end_s));
    return out;
  };
  if (!costs.has_grid()) {
    scoring.free_path = {stretch(from_s, goal_s)};
  } else {
    // The free run under way: [run_start, run_end] while in_run.
    bool in_run = false;
    double run_start = from_s;
    double run_end = from_s;
    for (double s = from_s;; s = std::min(s + sample_m, goal_s)) {
      const geometry::Point2D p = path.point_at(s);
      if (costs.cost(p.x, p.y) < PlanningGrid::kLethal) {
        if (!in_run) run_start = s;
        in_run = true;
        run_end = s;
      } else if (in_run) {
        scoring.free_path.push_back(stretch(run_start, run_end));
        in_run = false;
      }
      if (s >= goal_s) break;
    }
    if (in_run) scoring.free_path.push_back(stretch(run_start, run_end));
  }
  // The local goal must be a free cell: walk back along the path to the last free point.
  double local_goal_s = goal_s;
  while (local_goal_s > from_s) {
    const geometry::Point2D p = path.point_at(local_goal_s);
    if (PlanningGrid::is_traversable_cost(costs.cost(p.x, p.y))) break;
    local_goal_s = std::max(from_s, local_goal_s - sample_m);
  }
  scoring.local_goal = path.point_at(local_goal_s);
  const double goal_heading = path.heading_at(local_goal_s);
  scoring.goal_front = {scoring.local_goal.x + o.forward_point_distance_m * std::cos(goal_heading),
                        scoring.local_goal.y + o.forward_point_distance_m * std::sin(goal_heading)};
  scoring.alignment_scale = progress_.status().distance_to_goal_m > o.forward_point_distance_m
                                ? o.path_distance_bias
                                : 0.0;

  // Standing still is the score to beat; from an inscribed or lethal cell nothing is admissible.
  const std::uint8_t here = costs.cost(pose.x, pose.y);
  const double stay_score = scoring.score(o, pose, here);
  const bool accelerate = o.accelerate_in_rollout;
  DynamicLimits sampling = o.limits;
  if (accelerate) sampling.control_period_s = o.sim_time_s;
  const DynamicWindow window = reachable_window(sampling, velocity);
  const msgs::Twist from{std::isfinite(velocity.linear_mps) ? velocity.linear_mps : 0.0,
                         std::isfinite(velocity.angular_radps) ? velocity.angular_radps : 0.0};
  // One trajectory: constant (v, w), or accelerating from the measured velocity to it.
  const auto simulate = [&](double v, double w, int steps, auto&& visit) {
    if (accelerate) {
      roll_out_accelerating(pose, from, {v, w}, o.limits, steps, o.sim_time_s / steps, visit);
    } else {
      roll_out(pose, v, w, steps, o.sim_time_s / steps, visit);
    }
  };
  double best_score = std::numeric_limits<double>::infinity();
  msgs::Twist best;
  int best_steps = 0;
  bool found = false;
  if (PlanningGrid::is_traversable_cost(here)) {
    for (const double v : samples(window.min_linear_mps, window.max_linear_mps, o.linear_samples)) {
      for (const double w :
           samples(window.min_angular_radps, window.max_angular_radps, o.angular_samples)) {
        const double fastest_v =
            accelerate ? std::max(std::abs(v), std::abs(from.linear_mps)) : std::abs(v);
        const double fastest_w =
            accelerate ? std::max(std::abs(w), std::abs(from.angular_radps)) : std::abs(w);
        const int steps = static_cast<int>(
            std::ceil(std::max(fastest_v * o.sim_time_s / o.sim_granularity_m,
                               fastest_w * o.sim_time_s / o.angular_sim_granularity_rad)));
        if (steps == 0) continue;  // standing still: stay_score
        ++scored_;
        std::uint8_t max_cost = here;
        bool admissible = true;
        geometry::Pose2D end = pose;
        simulate(v, w, steps, [&](const geometry::Pose2D& at) {
          const std::uint8_t cost = costs.cost(at.x, at.y);
          admissible = PlanningGrid::is_traversable_cost(cost);
          max_cost = std::max(max_cost, cost);
          end = at;
          return admissible;
        });
        if (!admissible) continue;
        ++admissible_;
        const double score = scoring.score(o, end, max_cost);
        const bool better =
            score < best_score - 1e-9 || (score <= best_score + 1e-9 && v > best.linear_mps);
        if (!found || better) {
          found = true;
          best_score = score;
          best = {v, w};
          best_steps = steps;
        }
      }
    }
  }
  blocked_ = !found || best_score > stay_score - o.min_improvement;
  if (blocked_) {
    const auto toward_goal = approach_goal(pose, velocity);
    blocked_ = !toward_goal;
    return toward_goal.value_or(msgs::Twist{});
  }
  chosen_.push_back(pose);
  simulate(best.linear_mps, best.angular_radps, best_steps, [this](const geometry::Pose2D& at) {
    chosen_.push_back(at);
    return true;
  });
  // Trajectory Rollout commands the sample itself: the velocity smoother ramps to it at the limits
  // as the simulation did. (A step of one period from the measured velocity would be held back by
  // the measurement's lag behind the command, 50 ms of it at the odometry's 0.1 s window.)
  return best;
}

std::optional<msgs::Twist> DwaTracker::approach_goal(const geometry::Pose2D& pose,
                                                     const msgs::Twist& velocity) const {
  const geometry::Point2D goal = progress_.path().back();
  const double distance_m = std::hypot(goal.x - pose.x, goal.y - pose.y);
  if (distance_m > options_.approach_radius_m) return std::nullopt;
  const CostLookup costs(costmap_.get());
  const double step_m = costs.has_grid() ? costmap_->resolution_m() : std::max(distance_m, 1e-3);
  for (double s = 0.0; s <= distance_m; s += step_m) {
    const double f = distance_m > 0.0 ? s / distance_m : 0.0;
    if (!PlanningGrid::is_traversable_cost(
            costs.cost(pose.x + f * (goal.x - pose.x), pose.y + f * (goal.y - pose.y)))) {
      return std::nullopt;
    }
  }
  const double bearing_error =
      geometry::wrap_angle(pose.theta - std::atan2(goal.y - pose.y, goal.x - pose.x));
  // Facing the goal within this, drive; the tolerance's own angle seen from here, at least.
  const double facing_rad = std::max(0.1, std::atan2(options_.goal_tolerance_m, distance_m));
  if (std::abs(bearing_error) > facing_rad) {
    return stop_and_rotate(options_.limits, velocity, bearing_error, facing_rad).command;
  }
  const DynamicWindow window = reachable_window(options_.limits, velocity);
  // Slow enough to stop at the goal: v = sqrt(2 a d).
  const double v = std::sqrt(2.0 * options_.limits.linear_accel_mps2 * distance_m);
  return window.clamp({v, 0.0});
}

}  // namespace mobot::control
