#include "server/planning_worker.h"

#include <boost/asio/post.hpp>

#include <stdexcept>
#include "core/geometry/simple_polygon.h"
#include "core/planning/turning_radius_fillet.h"

#include <spdlog/spdlog.h>

namespace mobot::server {

PlanningWorker::PlanningWorker(planning::PlanningGridOptions grid_options,
                               const PluginSet<planning::GlobalPlanner>& planners,
                               double min_turning_radius_m)
    : builder_(grid_options), min_turning_radius_m_(min_turning_radius_m), plugins_(planners) {}

PlanningWorker::~PlanningWorker() { pool_.join(); }

planning::PlanningGrid PlanningWorker::build(
    const mapping::OccupancyGrid& map, const mapping::OccupancyGrid* layer,
    std::span<const geometry::Point2D> points,
    std::span<const std::vector<geometry::Point2D>> zones) const {
  const std::span<const mapping::OccupancyGrid> layers(layer, layer ? 1 : 0);
  return builder_.build(map, {layers, points, zones});
}

void PlanningWorker::set_map(const mapping::OccupancyGrid& map,
                             std::vector<std::vector<geometry::Point2D>> zones,
                             std::uint64_t generation) {
  auto copy = std::make_shared<const mapping::OccupancyGrid>(map);
  auto kept = std::make_shared<const std::vector<std::vector<geometry::Point2D>>>(std::move(zones));
  auto grid = std::make_shared<const planning::PlanningGrid>(build(*copy, nullptr, {}, *kept));
  std::lock_guard lock(mutex_);
  map_ = std::move(copy);
  zones_ = std::move(kept);
  layer_.reset();
  static_grid_ = std::move(grid);
  generation_ = generation;
}

bool PlanningWorker::set_obstacle_layer(std::shared_ptr<const mapping::OccupancyGrid> layer,
                                        std::uint64_t map_generation) {
  std::shared_ptr<const mapping::OccupancyGrid> map;
  std::shared_ptr<const std::vector<std::vector<geometry::Point2D>>> zones;
  {
    std::lock_guard lock(mutex_);
    if (map_generation != generation_ || !map_) return false;
    map = map_;
    zones = zones_;
  }
  auto grid = std::make_shared<const planning::PlanningGrid>(build(*map, layer.get(), {}, *zones));
  std::lock_guard lock(mutex_);
  if (map_generation != generation_) return false;  // a new map arrived while this one inflated
  layer_ = std::move(layer);
  static_grid_ = std::move(grid);
  return true;
}

std::shared_ptr<const planning::PlanningGrid> PlanningWorker::static_grid() const {
  std::lock_guard lock(mutex_);
  return static_grid_;
}

void PlanningWorker::plan(
    const geometry::Pose2D& start, const geometry::Pose2D& goal, const std::string& planner,
    std::shared_ptr<const std::vector<geometry::Point2D>> extra_obstacles_in_map, Done done) {
  boost::asio::post(pool_, [this, start, goal, planner, extra = std::move(extra_obstacles_in_map),
                            done = std::move(done)] {
    Outcome outcome;
    try {
      outcome = plan_now(start, goal, planner, extra ? *extra : std::vector<geometry::Point2D>{});
    } catch (const std::exception& error) {
      // A planner that throws (a name nobody checked, an allocation) must not take the worker
      // thread down: the goal fails to plan.
      spdlog::error("planning with '{}' failed: {}", planner, error.what());
      outcome = {planning::PlanError::kNoPath, {}};
    }
    done(std::move(outcome));
  });
}

std::future<PlanningWorker::Outcome> PlanningWorker::plan(
    const geometry::Pose2D& start, const geometry::Pose2D& goal, const std::string& planner,
    std::shared_ptr<const std::vector<geometry::Point2D>> extra_obstacles_in_map) {
  auto promise = std::make_shared<std::promise<Outcome>>();
  std::future<Outcome> result = promise->get_future();
  plan(start, goal, planner, std::move(extra_obstacles_in_map),
       [promise](Outcome outcome) { promise->set_value(std::move(outcome)); });
  return result;
}

planning::GlobalPlanner& PlanningWorker::planner_named(const std::string& name) {
  auto& planner = planners_[name];
  if (!planner) planner = plugins_.make(name);
  if (!planner) throw std::invalid_argument("unknown planner '" + name + "'");
  return *planner;
}

PlanningWorker::Outcome PlanningWorker::plan_now(
    const geometry::Pose2D& start, const geometry::Pose2D& goal, const std::string& planner,
    const std::vector<geometry::Point2D>& extra_obstacles_in_map) {
  std::shared_ptr<const mapping::OccupancyGrid> map;
  std::shared_ptr<const mapping::OccupancyGrid> layer;
  std::shared_ptr<const planning::PlanningGrid> grid;
  std::shared_ptr<const std::vector<std::vector<geometry::Point2D>>> zones;
  {
    std::lock_guard lock(mutex_);
    map = map_;
    layer = layer_;
    grid = static_grid_;
    zones = zones_;
  }
  if (!grid) return {planning::PlanError::kNoMap, {}};
  for (const auto& zone : *zones) {
    if (geometry::SimplePolygon(zone).contains({goal.x, goal.y})) {
      return {planning::PlanError::kGoalInKeepout, {}};
    }
  }
  if (!extra_obstacles_in_map.empty()) {
    grid = std::make_shared<const planning::PlanningGrid>(
        build(*map, layer.get(), extra_obstacles_in_map, *zones));
  }
  planning::GlobalPlanner& global_planner = planner_named(planner);
  const planning::PlanResult result = global_planner.plan(*grid, start, goal);
  if (!result.ok()) return {result.error, {}};
  if (!global_planner.route_may_be_smoothed()) {
    return {std::nullopt, planning::Path(result.points_in_map)};
  }
  if (min_turning_radius_m_ <= 0.0) {
    return {std::nullopt, planning::Path(smoother_.smooth(*grid, result.points_in_map))};
  }
  // Round the shortcut polyline's corners first, then space its waypoints as the smoother does.
  planning::TurningRadiusFilletOptions fillet;
  fillet.min_turning_radius_m = min_turning_radius_m_;
  fillet.max_cost = smoother_options_.max_shortcut_cost;
  const std::vector<geometry::Point2D> rounded =
      planning::fillet_corners(*grid, smoother_.shortcut(*grid, result.points_in_map), fillet);
  return {std::nullopt, planning::Path(planning::PathSmoother::densify(
                            rounded, smoother_options_.waypoint_spacing_m))};
}

}  // namespace mobot::server
