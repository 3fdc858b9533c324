#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/planning/global_planner.h"
#include "core/planning/planning_grid.h"
#include "core/planning/voronoi_roadmap.h"

namespace mobot::planning {

struct VoronoiPlannerOptions {
  VoronoiRoadmapOptions roadmap;
  // A step onto a cell off the roadmap costs its length times this; onto a roadmap cell, its
  // length. 4 makes the planner take the passage middles unless they are a detour of more than
  // four times the direct way. At least 1 (the search's heuristic, the octile distance, then never
  // overestimates); 1 ignores the roadmap: shortest paths.
  double off_roadmap_factor = 4.0;
  // As AStarOptions::max_escape_distance_m: a start inside the inflated zone escapes to the nearest
  // traversable cell within this distance instead of failing.
  double max_escape_distance_m = 0.5;
  // points_in_map is reduced by Douglas-Peucker to the points where the path turns by more than
  // this deviation. The roadmap is a raster line whose cells lie up to about half a cell (and on a
  // diagonal a staircase up to 0.7 cell) off the true bisector: 0.05 m, one cell at the default map
  // resolution, absorbs that noise, while a larger value starts cutting the bends of the passage
  // middles the path is meant to follow. 0 drops only collinear points.
  double waypoint_tolerance_m = 0.05;
};

// docs/algorithms.md C1: the Voronoi roadmap planner. The path runs from the start to the nearest
// roadmap cell, along the roadmap (the middles of passages wider than the robot, see
// VoronoiRoadmap) and off it to the goal, found by one A* over the traversable cells in which a
// step onto a roadmap cell costs its length and a step onto any other traversable cell its length
// times off_roadmap_factor. One search instead of three legs (start to roadmap, along it, to the
// goal) means a path exists whenever A* finds one, even where the roadmap is broken into pieces,
// and the path still follows the roadmap wherever it connects. 8-connected, no corner cutting,
// octile heuristic (admissible: every step costs at least its length), so the path is optimal for
// that cost model.
//
// Same validation, error codes and start escape as AStarPlanner. The result's cells are the whole
// 8-connected path; points_in_map is reduced to the waypoints where the path turns (see
// reduce_to_waypoints), each segment inside traversable cells; length_m is along those waypoints;
// cost is the search's (metres, those off the roadmap times the factor) plus the escape's length.
//
// The roadmap depends only on the grid: it is built on the first plan and kept as long as the
// grid's size, resolution, origin and costs stay the same (compared with a copy of the grid: exact,
// and at 1 byte a cell a fifth of what the roadmap itself holds).
class VoronoiPlanner : public GlobalPlanner {
 public:
  // Throws std::invalid_argument on invalid options (see VoronoiPlannerOptions).
  explicit VoronoiPlanner(const VoronoiPlannerOptions& options = {});

  std::string_view name() const override { return "voronoi"; }
  // Smoothing would cut the roadmap's bends back to the shortest path; the waypoints are already
  // reduced and clear.
  bool route_may_be_smoothed() const override { return false; }
  PlanResult plan(const PlanningGrid& grid, const geometry::Pose2D& start,
                  const geometry::Pose2D& goal) override;

  const VoronoiPlannerOptions& options() const { return options_; }
  // The roadmap of `grid`: the cached one when the grid is unchanged, else built now.
  const VoronoiRoadmap& roadmap_for(const PlanningGrid& grid);
  // How many roadmaps this planner has built (tests check the cache with it).
  std::size_t roadmap_builds() const { return roadmap_builds_; }

 private:
  struct Node {
    std::uint64_t f;  // bits of the double f = g + h: the exact key
    std::uint32_t h;  // bits of the float h: a tie-break only, so optimality does not depend on it
    std::uint32_t index;
  };

  // Resets the search state for a grid of `cell_count` cells.
  void begin_search(std::size_t cell_count);
  // Fills `result.cells` (appending) and `result.cost`; false when the goal is unreachable.
  bool search(const PlanningGrid& grid, const VoronoiRoadmap& roadmap, mapping::CellIndex start,
              mapping::CellIndex goal, PlanResult& result);

  VoronoiPlannerOptions options_;

  // The roadmap and a copy of the grid it was built from.
  VoronoiRoadmap roadmap_;
  std::optional<PlanningGrid> roadmap_grid_;
  std::size_t roadmap_builds_ = 0;

  // Search state, valid for a cell only while visit_[cell] holds the current search number, so
  // a plan does not reset a million cells. state_: bits 0..2 the step that reached the cell (its
  // parent), bit 3 closed.
  std::vector<double> g_;
  std::vector<std::uint32_t> visit_;
  std::vector<std::uint8_t> state_;
  std::uint32_t search_number_ = 0;
  std::vector<Node> open_;
};

// Douglas-Peucker on a path's points, with one addition: a segment is kept only when every cell
// it touches is traversable (line_of_sight.h), else it is split further, so the robot never cuts
// a corner of the inflated zone that the cell path went around. The first and last points are
// kept exactly. `points` must be a path whose consecutive points are clear of each other (a
// planner's cell path is): then the result is too. Throws std::invalid_argument on a negative or
// non-finite tolerance.
std::vector<geometry::Point2D> reduce_to_waypoints(const PlanningGrid& grid,
                                                   std::span<const geometry::Point2D> points,
                                                   double tolerance_m);

}  // namespace mobot::planning
