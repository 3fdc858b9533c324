#pragma once

#include <cstdint>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <boost/asio/thread_pool.hpp>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "core/planning/global_planner.h"
#include "core/planning/path.h"
#include "core/planning/path_smoother.h"
#include "core/planning/planning_grid.h"
#include "core/planning/planning_grid_builder.h"
#include "server/plugins/registry.h"

namespace mobot::server {

// Global planning off the control loop: one worker thread owns the planners (they keep scratch
// memory between plans), plans run one after another, and callers get a future. The static
// planning grid (the active map, inflated) is built once per map; obstacles the laser sees that
// the map does not have are added for a plan when given.
class PlanningWorker {
 public:
  struct Outcome {
    std::optional<planning::PlanError> error;
    planning::Path path;  // smoothed, map frame
  };

  using Done = std::function<void(Outcome)>;

  // `planners` must outlive the worker; each planner is made on first use, on the worker thread.
  // A car-like base's plans get their corners rounded to `min_turning_radius_m` (0: none).
  PlanningWorker(planning::PlanningGridOptions grid_options,
                 const PluginSet<planning::GlobalPlanner>& planners,
                 double min_turning_radius_m = 0.0);
  ~PlanningWorker();
  PlanningWorker(const PlanningWorker&) = delete;
  PlanningWorker& operator=(const PlanningWorker&) = delete;

  // Inflates `map` (on the caller's thread) and plans on it from now on, without a 3D layer.
  // `generation` names the activation, which set_obstacle_layer must name.
  // `zones` are the map's keep-out polygons: lethal and inflated, and a goal inside one is refused.
  void set_map(const mapping::OccupancyGrid& map, std::vector<std::vector<geometry::Point2D>> zones,
               std::uint64_t generation);
  // Merges the 3D-obstacle layer (occupied cells block) into the static grid, rebuilt on the
  // caller's thread. Ignored (false) when the map changed since `map_generation`.
  bool set_obstacle_layer(std::shared_ptr<const mapping::OccupancyGrid> layer,
                          std::uint64_t map_generation);
  // The inflated active map, or null before set_map.
  std::shared_ptr<const planning::PlanningGrid> static_grid() const;

  // Plans on the worker thread and calls `done` there with the outcome. `planner` must be a name
  // the plugin set knows (the caller checks).
  void plan(const geometry::Pose2D& start, const geometry::Pose2D& goal, const std::string& planner,
            std::shared_ptr<const std::vector<geometry::Point2D>> extra_obstacles_in_map,
            Done done);
  // The same, for a caller that polls.
  std::future<Outcome> plan(
      const geometry::Pose2D& start, const geometry::Pose2D& goal, const std::string& planner,
      std::shared_ptr<const std::vector<geometry::Point2D>> extra_obstacles_in_map);

 private:
  Outcome plan_now(const geometry::Pose2D& start, const geometry::Pose2D& goal,
                   const std::string& planner,
                   const std::vector<geometry::Point2D>& extra_obstacles_in_map);
  planning::GlobalPlanner& planner_named(const std::string& name);

  planning::PlanningGrid build(const mapping::OccupancyGrid& map,
                               const mapping::OccupancyGrid* layer,
                               std::span<const geometry::Point2D> points,
                               std::span<const std::vector<geometry::Point2D>> zones) const;

  const planning::PlanningGridBuilder builder_;
  const double min_turning_radius_m_;
  const planning::PathSmootherOptions smoother_options_;
  const planning::PathSmoother smoother_{smoother_options_};
  const PluginSet<planning::GlobalPlanner>& plugins_;

  mutable std::mutex mutex_;  // guards map_, layer_, generation_ and static_grid_
  std::shared_ptr<const mapping::OccupancyGrid> map_;
  std::shared_ptr<const mapping::OccupancyGrid> layer_;
  std::shared_ptr<const std::vector<std::vector<geometry::Point2D>>> zones_;
  std::uint64_t generation_ = 0;
  std::shared_ptr<const planning::PlanningGrid> static_grid_;

  // Used only on the worker thread.
  std::map<std::string, std::unique_ptr<planning::GlobalPlanner>> planners_;
  boost::asio::thread_pool pool_{1};
};

}  // namespace mobot::server
