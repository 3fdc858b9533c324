#include "server/navigation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace mobot::server {
namespace {

// A return within this many cells of a wall in the map is that wall.
constexpr int kMapMatchCells = 2;
// Arc samples across a sonar cone: the echo may come from anywhere in it, not only its axis.
constexpr int kConeSamples = 5;

navigation::GoalNavigatorOptions navigator_options(const Config& config) {
  navigation::GoalNavigatorOptions options;
  auto& follower = options.tracker.lyapunov;
  follower.goal_tolerance_m = config.navigation.goal_tolerance_m;
  follower.goal_tolerance_rad = config.navigation.goal_tolerance_rad;
  follower.max_linear_mps = config.navigation.max_linear_mps;
  follower.max_angular_radps = config.robot.limits.max_angular_radps;
  // Point stabilisation swings the body on a curve; started late it happens where the path
  // ended (a goal just past a door must not be approached with the footprint in the doorway).
  follower.final_approach_m = 0.4;
  options.avoidance.influence_distance_m = config.navigation.avoidance_distance_m;
  options.avoidance.max_angular_radps = config.robot.limits.max_angular_radps;
  return options;
}

planning::PlanningGridOptions grid_options(const Config& config) {
  planning::PlanningGridOptions options;
  options.inscribed_radius_m = config.navigation.inscribed_radius_m;
  return options;
}

double distance_to_polyline(const std::vector<geometry::Point2D>& path, geometry::Point2D point) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const double dx = path[i + 1].x - path[i].x;
    const double dy = path[i + 1].y - path[i].y;
    const double length2 = dx * dx + dy * dy;
    const double along =
        length2 > 0.0 ? ((point.x - path[i].x) * dx + (point.y - path[i].y) * dy) / length2 : 0.0;
    const double f = std::clamp(along, 0.0, 1.0);
    best = std::min(best, std::hypot(path[i].x + f * dx - point.x, path[i].y + f * dy - point.y));
  }
  return best;
}

}  // namespace

Navigation::Navigation(const Config& config)
    : blocking_distance_m_(config.navigation.inscribed_radius_m),
      worker_(grid_options(config)),
      navigator_(navigator_options(config)) {}

std::future<PlanningWorker::Outcome> Navigation::plan(const geometry::Pose2D& start,
                                                      const GoalRequest& request) {
  return worker_.plan(start, request.target, request.planner, unexpected_points_);
}

const navigation::Goal& Navigation::start(const GoalRequest& request, const planning::Path& path,
                                          double now_s) {
  navigation::Goal goal;
  goal.id = next_goal_id_++;
  goal.target = request.target;
  goal.has_heading = request.has_heading;
  goal.planner = request.planner;
  goal.controller = request.controller;
  replan_.reset();
  return navigator_.start(std::move(goal), path, now_s);
}

bool Navigation::explained_by_map(const geometry::Point2D& point_in_map) const {
  const auto grid = worker_.static_grid();
  if (!grid) return true;
  const auto cell = grid->cell_at(point_in_map);
  if (!cell) return true;  // beyond the map: nothing to plan around
  for (int dy = -kMapMatchCells; dy <= kMapMatchCells; ++dy) {
    for (int dx = -kMapMatchCells; dx <= kMapMatchCells; ++dx) {
      const mapping::CellIndex near{cell->x + dx, cell->y + dy};
      if (grid->contains(near) && grid->cost(near) >= planning::PlanningGrid::kLethal) return true;
    }
  }
  return false;
}


bool Navigation::near_active_path(const geometry::Point2D& point_in_map, double within_m) const {
  const auto id = navigator_.active_id();
  if (!id) return false;
  return distance_to_polyline(navigator_.find(*id)->path, point_in_map) < within_m;
}

void Navigation::request_replan(const geometry::Pose2D& pose, double now_s) {
  const auto id = navigator_.active_id();
  if (!id || replan_) return;
  const auto goal = navigator_.find(*id);
  GoalRequest request;
  request.target = goal->target;
  request.planner = goal->planner;
  replan_ = PendingReplan{goal->id, plan(pose, request)};
  last_replan_s_ = now_s;
}

void Navigation::observe_scan(const msgs::LaserScan& scan, const geometry::Pose2D& sensor_in_map,
                              const geometry::Pose2D& base_in_map, double now_s) {
  unexpected_points_.clear();
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const float range_m = scan.ranges_m[i];
    if (!(range_m >= scan.range_min_m && range_m <= scan.range_max_m)) continue;
    const double angle_rad = scan.angle_min_rad + static_cast<double>(i) * scan.angle_increment_rad;
    const geometry::Point2D point = geometry::transform_point(
        sensor_in_map, {range_m * std::cos(angle_rad), range_m * std::sin(angle_rad)});
    if (!explained_by_map(point)) unexpected_points_.push_back(point);
  }
  // Seen from afar by the laser, an obstacle on the path is planned around before the sonar
  // has to swerve; at most once a second, so a person walking along does not thrash the planner.
  constexpr double kReplanInterval_s = 1.0;
  if (now_s - last_replan_s_ < kReplanInterval_s) return;
  for (const auto& point : unexpected_points_) {
    if (near_active_path(point, blocking_distance_m_)) {
      request_replan(base_in_map, now_s);
      return;
    }
  }
}

void Navigation::observe_sonar(const msgs::SonarRing& ring, const geometry::Pose2D& base_in_map) {
  unexpected_echoes_.clear();
  for (const auto& reading : ring.readings) {
    msgs::RangeReading echo = reading;
    if (reading.range_m < reading.range_max_m) {
      const geometry::Pose2D sensor = geometry::compose(base_in_map, reading.sensor_in_base);
      bool wall = false;
      for (int k = 0; k < kConeSamples && !wall; ++k) {
        const double angle_rad =
            reading.cone_rad * (static_cast<double>(k) / (kConeSamples - 1) - 0.5);
        wall = explained_by_map(geometry::transform_point(
            sensor, {reading.range_m * std::cos(angle_rad), reading.range_m * std::sin(angle_rad)}));
      }
      const geometry::Point2D axis_point = geometry::transform_point(sensor, {reading.range_m, 0.0});
      // A wall on the map, or something the path already keeps clear of, is the planner's
      // business; the potential field is for what stands on the path and the map does not show.
      if (wall || !near_active_path(axis_point, blocking_distance_m_ + 0.1)) {
        echo.range_m = reading.range_max_m;
      }
    }
    unexpected_echoes_.push_back(echo);
  }
}

void Navigation::collect_replan(double now_s) {
  if (!replan_ ||
      replan_->outcome.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    return;
  }
  PlanningWorker::Outcome outcome = replan_->outcome.get();
  const std::int64_t goal_id = replan_->goal_id;
  replan_.reset();
  if (navigator_.active_id() != goal_id) return;
  if (outcome.error) {
    navigator_.end_active(navigation::GoalStatus::kFailed,
                          std::string(planning::error_code(*outcome.error)), now_s);
  } else {
    navigator_.replan(goal_id, outcome.path, now_s);
  }
}

std::optional<msgs::Twist> Navigation::tick(double now_s, const geometry::Pose2D& pose,
                                            const msgs::Twist& velocity) {
  collect_replan(now_s);
  const auto result = navigator_.tick(now_s, pose, velocity, unexpected_echoes_);
  if (result.replan_needed) request_replan(pose, now_s);
  return result.command;
}

}  // namespace mobot::server
