#include "server/planning_worker.h"

#include <boost/asio/post.hpp>
#include <stdexcept>

#include "core/planning/global_planner_factory.h"

namespace mobot::server {

namespace {

planning::GlobalPlannerOptions planner_options(const planning::PlanningGridOptions& grid) {
  planning::GlobalPlannerOptions options;
  // The roadmap keeps the middles of passages the robot fits through: at least its turning
  // diameter wide.
  options.voronoi.roadmap.min_passage_width_m = 2.0 * grid.inscribed_radius_m;
  return options;
}

}  // namespace

PlanningWorker::PlanningWorker(planning::PlanningGridOptions grid_options)
    : builder_(grid_options), planner_options_(planner_options(grid_options)) {}

PlanningWorker::~PlanningWorker() { pool_.join(); }

std::uint64_t PlanningWorker::set_map(const mapping::OccupancyGrid& map) {
  auto copy = std::make_shared<const mapping::OccupancyGrid>(map);
  auto grid = std::make_shared<const planning::PlanningGrid>(builder_.build(*copy));
  std::lock_guard lock(mutex_);
  map_ = std::move(copy);
  layer_.reset();
  static_grid_ = std::move(grid);
  return ++generation_;
}

bool PlanningWorker::set_obstacle_layer(std::shared_ptr<const mapping::OccupancyGrid> layer,
                                        std::uint64_t map_generation) {
  std::shared_ptr<const mapping::OccupancyGrid> map;
  {
    std::lock_guard lock(mutex_);
    if (map_generation != generation_ || !map_) return false;
    map = map_;
  }
  const std::span<const mapping::OccupancyGrid> layers(layer.get(), layer ? 1 : 0);
  auto grid = std::make_shared<const planning::PlanningGrid>(builder_.build(*map, {layers, {}}));
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

std::future<PlanningWorker::Outcome> PlanningWorker::plan(
    const geometry::Pose2D& start, const geometry::Pose2D& goal, const std::string& planner,
    std::vector<geometry::Point2D> extra_obstacles_in_map) {
  auto task = std::make_shared<std::packaged_task<Outcome()>>(
      [this, start, goal, planner, extra = std::move(extra_obstacles_in_map)] {
        return plan_now(start, goal, planner, extra);
      });
  std::future<Outcome> result = task->get_future();
  boost::asio::post(pool_, [task] { (*task)(); });
  return result;
}

planning::GlobalPlanner& PlanningWorker::planner_named(const std::string& name) {
  auto& planner = planners_[name];
  if (!planner) planner = planning::make_global_planner(name, planner_options_);
  if (!planner) throw std::invalid_argument("unknown planner '" + name + "'");
  return *planner;
}

PlanningWorker::Outcome PlanningWorker::plan_now(
    const geometry::Pose2D& start, const geometry::Pose2D& goal, const std::string& planner,
    const std::vector<geometry::Point2D>& extra_obstacles_in_map) {
  std::shared_ptr<const mapping::OccupancyGrid> map;
  std::shared_ptr<const mapping::OccupancyGrid> layer;
  std::shared_ptr<const planning::PlanningGrid> grid;
  {
    std::lock_guard lock(mutex_);
    map = map_;
    layer = layer_;
    grid = static_grid_;
  }
  if (!grid) return {planning::PlanError::kNoMap, {}};
  if (!extra_obstacles_in_map.empty()) {
    const std::span<const mapping::OccupancyGrid> layers(layer.get(), layer ? 1 : 0);
    grid = std::make_shared<const planning::PlanningGrid>(
        builder_.build(*map, {layers, extra_obstacles_in_map}));
  }
  planning::GlobalPlanner& global_planner = planner_named(planner);
  const planning::PlanResult result = global_planner.plan(*grid, start, goal);
  if (!result.ok()) return {result.error, {}};
  if (!global_planner.route_may_be_smoothed()) {
    return {std::nullopt, planning::Path(result.points_in_map)};
  }
  return {std::nullopt, planning::Path(smoother_.smooth(*grid, result.points_in_map))};
}

}  // namespace mobot::server
