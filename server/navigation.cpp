#include "server/navigation.h"

#include <chrono>
#include <cmath>

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
  options.avoidance.influence_distance_m = config.navigation.avoidance_distance_m;
  options.avoidance.max_angular_radps = config.robot.limits.max_angular_radps;
  return options;
}

planning::PlanningGridOptions grid_options(const Config& config) {
  planning::PlanningGridOptions options;
  options.inscribed_radius_m = config.navigation.inscribed_radius_m;
  return options;
}

}  // namespace

Navigation::Navigation(const Config& config)
    : worker_(grid_options(config)), navigator_(navigator_options(config)) {}

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

void Navigation::observe_scan(const msgs::LaserScan& scan, const geometry::Pose2D& sensor_in_map) {
  unexpected_points_.clear();
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const float range_m = scan.ranges_m[i];
    if (!(range_m >= scan.range_min_m && range_m <= scan.range_max_m)) continue;
    const double angle_rad = scan.angle_min_rad + static_cast<double>(i) * scan.angle_increment_rad;
    const geometry::Point2D point = geometry::transform_point(
        sensor_in_map, {range_m * std::cos(angle_rad), range_m * std::sin(angle_rad)});
    if (!explained_by_map(point)) unexpected_points_.push_back(point);
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
      // A wall on the map is the planner's business; the potential field is for what is not.
      if (wall) echo.range_m = reading.range_max_m;
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
  if (result.replan_needed) {
    const auto goal = navigator_.find(*navigator_.active_id());
    GoalRequest request;
    request.target = goal->target;
    request.planner = goal->planner;
    replan_ = PendingReplan{goal->id, plan(pose, request)};
  }
  return result.command;
}

}  // namespace mobot::server
