#include "core/planning/voronoi_planner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <queue>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/mapping/occupancy_grid.h"
#include "core/planning/astar_planner.h"
#include "core/planning/line_of_sight.h"
#include "core/planning/planning_grid_builder.h"
#include "core/planning/voronoi_planner.h"
#include "tests/unit/core/planning/planning_test_maps.h"

namespace mobot::planning {
namespace {

using mapping::CellIndex;
using mapping::OccupancyGrid;

constexpr double kInf = std::numeric_limits<double>::infinity();

using test_maps::build;
using test_maps::fill;
using test_maps::free_map;
using test_maps::kRes;
using test_maps::outline;

geometry::Pose2D at(const PlanningGrid& grid, CellIndex cell) {
  const geometry::Point2D p = grid.cell_center(cell);
  return {p.x, p.y, 0.0};
}

bool step_allowed(const PlanningGrid& grid, CellIndex from, CellIndex to) {
  if (!grid.is_traversable(to)) return false;
  if (from.x != to.x && from.y != to.y) {
    return grid.is_traversable({to.x, from.y}) && grid.is_traversable({from.x, to.y});
  }
  return true;
}

// Rooms, furniture and unknown patches: random rectangles inside an outline.
PlanningGrid random_map(std::mt19937& rng, int side) {
  OccupancyGrid map = free_map(side, side);
  outline(map);
  std::uniform_int_distribution<int> coordinate(0, side - 1);
  std::uniform_int_distribution<int> extent(1, side / 4);
  std::uniform_int_distribution<int> count(3, 14);
  const int rectangles = count(rng);
  for (int k = 0; k < rectangles; ++k) {
    const int x = coordinate(rng);
    const int y = coordinate(rng);
    const bool thin_wall = k % 2 == 0;
    const int w = thin_wall ? (k % 4 == 0 ? 1 : extent(rng) * 3) : extent(rng);
    const int h = thin_wall ? (k % 4 == 0 ? extent(rng) * 3 : 1) : extent(rng);
    fill(map, x, y, std::min(side - 1, x + w), std::min(side - 1, y + h),
         k % 7 == 3 ? OccupancyGrid::kUnknown : OccupancyGrid::kOccupied);
  }
  return build(map);
}

// A random traversable cell (maps from random_map have plenty).
CellIndex random_free_cell(std::mt19937& rng, const PlanningGrid& grid) {
  std::uniform_int_distribution<int> ux(0, grid.width() - 1);
  std::uniform_int_distribution<int> uy(0, grid.height() - 1);
  for (;;) {
    const CellIndex cell{ux(rng), uy(rng)};
    if (grid.is_traversable(cell)) return cell;
  }
}

// The 8-connected legality of a plan: starts and ends at the right cells, no jumps, no corner
// cutting, every cell after the start's escape traversable.
void expect_legal_cells(const PlanningGrid& grid, const PlanResult& result, CellIndex start,
                        CellIndex goal) {
  ASSERT_TRUE(result.ok());
  ASSERT_EQ(result.cells.front(), start);
  ASSERT_EQ(result.cells.back(), goal);
  std::size_t first_traversable = 0;
  while (!grid.is_traversable(result.cells[first_traversable])) ++first_traversable;
  EXPECT_EQ(first_traversable > 0, result.start_escaped);
  for (std::size_t i = 1; i < result.cells.size(); ++i) {
    const CellIndex a = result.cells[i - 1];
    const CellIndex b = result.cells[i];
    ASSERT_LE(std::max(std::abs(a.x - b.x), std::abs(a.y - b.y)), 1);
    ASSERT_FALSE(a == b);
    if (i > first_traversable) {
      ASSERT_TRUE(step_allowed(grid, a, b)) << "blocked or corner cut";
    }
  }
}

// Every segment between consecutive waypoints after the escape stays in traversable cells.
void expect_clear_waypoints(const PlanningGrid& grid, const PlanResult& result) {
  std::size_t escape_points = 0;
  while (escape_points < result.cells.size() && !grid.is_traversable(result.cells[escape_points])) {
    ++escape_points;
  }
  for (std::size_t i = escape_points + 1; i < result.points_in_map.size(); ++i) {
    ASSERT_TRUE(segment_is_clear(grid, result.points_in_map[i - 1], result.points_in_map[i],
                                 PlanningGrid::kMaxInflated))
        << "waypoint segment " << i;
  }
}

// The x (map frame) where a polyline first crosses the line y = y_m, or nullopt.
std::optional<double> crossing_x(const std::vector<geometry::Point2D>& points, double y_m) {
  for (std::size_t i = 1; i < points.size(); ++i) {
    const geometry::Point2D a = points[i - 1];
    const geometry::Point2D b = points[i];
    if ((a.y - y_m) * (b.y - y_m) > 0.0 || a.y == b.y) continue;
    return a.x + (b.x - a.x) * (y_m - a.y) / (b.y - a.y);
  }
  return std::nullopt;
}

// An 8 x 6 m hall split at y = 3 m by a wall (rows 59 and 60) with two gaps: a wide one to the
// side (2.0 m, x 0.5..2.5 m, middle 1.5 m) and one straight ahead of x = 4 m (1.0 m, x 3.5..4.5 m).
PlanningGrid hall_with_two_gaps() {
  OccupancyGrid map = free_map(160, 120);
  outline(map);
  fill(map, 0, 59, 159, 60, OccupancyGrid::kOccupied);
  fill(map, 10, 59, 49, 60, OccupancyGrid::kFree);
  fill(map, 70, 59, 89, 60, OccupancyGrid::kFree);
  return build(map);
}

TEST(VoronoiPlanner, CrossesAWallThroughTheMiddleOfItsGaps) {
  const PlanningGrid grid = hall_with_two_gaps();
  VoronoiPlanner planner;
  AStarPlanner astar;
  const auto wall_cells_x = [](const PlanResult& r) {
    std::vector<int> xs;
    for (const CellIndex c : r.cells) {
      if (c.y == 59 || c.y == 60) xs.push_back(c.x);
    }
    return xs;
  };

  // Straight ahead: through the narrow gap's middle (x = 4.0 m, between cells 79 and 80).
  const PlanResult ahead = planner.plan(grid, {4.0, 1.0, 0.0}, {4.0, 5.0, 0.0});
  ASSERT_TRUE(ahead.ok());
  ASSERT_FALSE(wall_cells_x(ahead).empty());
  for (const int x : wall_cells_x(ahead)) EXPECT_LE(std::abs(x + 0.5 - 80.0), 1.0) << x;
  const auto ahead_x = crossing_x(ahead.points_in_map, 3.0);
  ASSERT_TRUE(ahead_x.has_value());
  EXPECT_NEAR(*ahead_x, 4.0, 0.1);

  // Off to the side, in line with x = 1.2 m: through the wide gap's middle (1.5 m), where A*
  // drives straight through, 0.3 m off it.
  const PlanResult side = planner.plan(grid, {1.2, 1.0, 0.0}, {1.2, 5.0, 0.0});
  ASSERT_TRUE(side.ok());
  ASSERT_FALSE(wall_cells_x(side).empty());
  for (const int x : wall_cells_x(side)) EXPECT_LE(std::abs(x + 0.5 - 30.0), 1.0) << x;
  const auto side_x = crossing_x(side.points_in_map, 3.0);
  ASSERT_TRUE(side_x.has_value());
  EXPECT_NEAR(*side_x, 1.5, 0.1);
  const auto astar_x =
      crossing_x(astar.plan(grid, {1.2, 1.0, 0.0}, {1.2, 5.0, 0.0}).points_in_map, 3.0);
  ASSERT_TRUE(astar_x.has_value());
  EXPECT_GT(std::abs(*astar_x - 1.5), 0.2);  // the case really tells the planners apart

  // The controller gets waypoints, not cell centres.
  EXPECT_LT(side.points_in_map.size(), side.cells.size() / 4);
  EXPECT_EQ(side.points_in_map.front(), (geometry::Point2D{1.2, 1.0}));
  EXPECT_EQ(side.points_in_map.back(), (geometry::Point2D{1.2, 5.0}));
  expect_clear_waypoints(grid, side);
  expect_clear_waypoints(grid, ahead);
}

TEST(VoronoiPlanner, FollowsTheRoadmapWhereItConnects) {
  const PlanningGrid grid = hall_with_two_gaps();
  VoronoiPlanner planner;
  const PlanResult result = planner.plan(grid, {0.7, 0.7, 0.0}, {7.3, 5.3, 0.0});
  ASSERT_TRUE(result.ok());
  const VoronoiRoadmap& roadmap = planner.roadmap_for(grid);
  std::size_t on = 0;
  for (const CellIndex c : result.cells) on += roadmap.on_roadmap(c) ? 1 : 0;
  // Only the legs from the start to the roadmap and from it to the goal are off it.
  EXPECT_GT(static_cast<double>(on), 0.8 * static_cast<double>(result.cells.size()));
}

TEST(VoronoiPlanner, StartInInflationEscapesToTheNearestFreeCell) {
  // As the A* test: a wall at x = 10 inflated over x 7..9, the robot at x = 8 touching it.
  PlanningGrid grid(20, 10, 0.1, {});
  for (int y = 0; y < 10; ++y) {
    grid.set_cost({10, y}, PlanningGrid::kLethal);
    for (int x = 7; x <= 9; ++x) grid.set_cost({x, y}, PlanningGrid::kInscribed);
    for (int x = 11; x <= 13; ++x) grid.set_cost({x, y}, PlanningGrid::kInscribed);
  }
  VoronoiPlanner planner;
  const PlanResult result = planner.plan(grid, at(grid, {8, 5}), at(grid, {2, 5}));
  ASSERT_TRUE(result.ok());
  EXPECT_TRUE(result.start_escaped);
  EXPECT_EQ(result.cells,
            (std::vector<CellIndex>{{8, 5}, {7, 5}, {6, 5}, {5, 5}, {4, 5}, {3, 5}, {2, 5}}));
  // The escape (0.2 m) plus 0.4 m off the roadmap (there is none here) at 4 times its length.
  EXPECT_NEAR(result.cost, 0.2 + 4.0 * 0.4, 1e-9);
  // The escape's points are kept; the straight rest is one segment.
  EXPECT_EQ(result.points_in_map,
            (std::vector<geometry::Point2D>{grid.cell_center({8, 5}), grid.cell_center({7, 5}),
                                            grid.cell_center({6, 5}), grid.cell_center({2, 5})}));
  EXPECT_NEAR(result.length_m, 0.6, 1e-9);

  // The escape never crosses the wall itself.
  EXPECT_EQ(planner.plan(grid, at(grid, {9, 5}), at(grid, {18, 5})).error, PlanError::kNoPath);
  VoronoiPlannerOptions options;
  options.max_escape_distance_m = 0.15;
  VoronoiPlanner strict(options);
  EXPECT_EQ(strict.plan(grid, at(grid, {9, 5}), at(grid, {2, 5})).error,
            PlanError::kStartInObstacle);
}

TEST(VoronoiPlanner, FindsAPathWheneverAStarDoes) {
  std::mt19937 rng(2024);
  AStarPlanner astar;
  VoronoiPlanner planner;
  int found = 0;
  int refused = 0;
  int escaped = 0;
  std::size_t on_roadmap = 0;
  std::size_t path_cells = 0;
  for (int map = 0; map < 50; ++map) {
    const PlanningGrid grid = random_map(rng, 90);
    const VoronoiRoadmap& roadmap = planner.roadmap_for(grid);
    std::uniform_int_distribution<int> coordinate(0, 89);
    for (int trial = 0; trial < 12; ++trial) {
      const CellIndex start{coordinate(rng), coordinate(rng)};
      const CellIndex goal{coordinate(rng), coordinate(rng)};
      const PlanResult reference = astar.plan(grid, at(grid, start), at(grid, goal));
      const PlanResult result = planner.plan(grid, at(grid, start), at(grid, goal));
      ASSERT_EQ(result.ok(), reference.ok()) << map << "/" << trial;
      if (!result.ok()) {
        EXPECT_EQ(*result.error, *reference.error);
        ++refused;
        continue;
      }
      ++found;
      escaped += result.start_escaped ? 1 : 0;
      expect_legal_cells(grid, result, start, goal);
      expect_clear_waypoints(grid, result);
      const double octile_m =
          kRes * (std::max(std::abs(goal.x - start.x), std::abs(goal.y - start.y)) +
                  (std::numbers::sqrt2 - 1.0) *
                      std::min(std::abs(goal.x - start.x), std::abs(goal.y - start.y)));
      EXPECT_GE(result.cost, octile_m - 1e-9);
      EXPECT_LE(result.points_in_map.size(), result.cells.size() + 1);
      for (const CellIndex c : result.cells) on_roadmap += roadmap.on_roadmap(c) ? 1 : 0;
      path_cells += result.cells.size();
    }
  }
  EXPECT_EQ(planner.roadmap_builds(), 50U);  // once per map, not per plan
  EXPECT_GT(found, 150);
  EXPECT_GT(refused, 50);
  EXPECT_GT(escaped, 5);
  EXPECT_GT(on_roadmap, path_cells / 3);  // the random maps do have roadmaps that paths use
}

// Dijkstra over the planner's cost model: 8-connected, no corner cutting, a step costs its length
// on the roadmap and off_roadmap_factor times it elsewhere.
double reference_cost(const PlanningGrid& grid, const VoronoiRoadmap& roadmap, double factor,
                      CellIndex start, CellIndex goal) {
  std::vector<double> dist(grid.costs().size(), kInf);
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  dist[grid.index_of(start)] = 0.0;
  open.push({0.0, grid.index_of(start)});
  while (!open.empty()) {
    const auto [d, index] = open.top();
    open.pop();
    if (d > dist[index]) continue;
    const CellIndex cell = grid.cell_of(index);
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const CellIndex next{cell.x + dx, cell.y + dy};
        if ((dx == 0 && dy == 0) || !grid.contains(next) || !step_allowed(grid, cell, next)) {
          continue;
        }
        const double length = grid.resolution_m() * (dx != 0 && dy != 0 ? std::numbers::sqrt2 : 1);
        const double nd = d + length * (roadmap.on_roadmap(next) ? 1.0 : factor);
        if (nd < dist[grid.index_of(next)]) {
          dist[grid.index_of(next)] = nd;
          open.push({nd, grid.index_of(next)});
        }
      }
    }
  }
  return dist[grid.index_of(goal)];
}

TEST(VoronoiPlanner, PathsAreOptimalForTheRoadmapCostModel) {
  // The octile heuristic must stay admissible with the roadmap discount: the cost equals a
  // brute-force Dijkstra's, for several factors.
  std::mt19937 rng(17);
  int compared = 0;
  for (const double factor : {1.0, 4.0, 25.0}) {
    VoronoiPlannerOptions options;
    options.off_roadmap_factor = factor;
    VoronoiPlanner planner(options);
    for (int map = 0; map < 6; ++map) {
      const PlanningGrid grid = random_map(rng, 60);
      const VoronoiRoadmap& roadmap = planner.roadmap_for(grid);
      for (int trial = 0; trial < 10; ++trial) {
        const CellIndex start = random_free_cell(rng, grid);
        const CellIndex goal = random_free_cell(rng, grid);
        const double reference = reference_cost(grid, roadmap, factor, start, goal);
        const PlanResult result = planner.plan(grid, at(grid, start), at(grid, goal));
        if (reference == kInf) {
          EXPECT_EQ(result.error, PlanError::kNoPath);
          continue;
        }
        ASSERT_TRUE(result.ok());
        EXPECT_NEAR(result.cost, reference, 1e-9) << factor << " " << map << "/" << trial;
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 60);
}

TEST(VoronoiPlanner, IsDeterministic) {
  std::mt19937 rng(8);
  const PlanningGrid grid = random_map(rng, 120);
  VoronoiPlanner planner;
  int planned = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const geometry::Pose2D start = at(grid, random_free_cell(rng, grid));
    const geometry::Pose2D goal = at(grid, random_free_cell(rng, grid));
    const PlanResult first = planner.plan(grid, start, goal);
    const PlanResult again = planner.plan(grid, start, goal);
    const PlanResult fresh = VoronoiPlanner().plan(grid, start, goal);
    for (const PlanResult* other : {&again, &fresh}) {
      ASSERT_EQ(first.error, other->error);
      ASSERT_EQ(first.cells, other->cells);
      ASSERT_EQ(first.points_in_map, other->points_in_map);
      ASSERT_EQ(first.cost, other->cost);
      ASSERT_EQ(first.expanded_cells, other->expanded_cells);
    }
    planned += first.ok() ? 1 : 0;
  }
  EXPECT_GT(planned, 10);
}

TEST(VoronoiPlanner, CachesTheRoadmapUntilTheGridChanges) {
  PlanningGrid grid = hall_with_two_gaps();
  VoronoiPlanner planner;
  const geometry::Pose2D start{4.0, 1.0, 0.0};
  const geometry::Pose2D goal{4.0, 5.0, 0.0};
  ASSERT_TRUE(planner.plan(grid, start, goal).ok());
  ASSERT_TRUE(planner.plan(grid, {1.0, 1.0, 0.0}, goal).ok());
  const PlanningGrid copy = grid;
  ASSERT_TRUE(planner.plan(copy, start, goal).ok());
  EXPECT_EQ(planner.roadmap_builds(), 1U);

  // Close the straight-ahead gap: a new roadmap, and the plan a fresh planner makes.
  for (int x = 70; x <= 89; ++x) {
    for (int y = 59; y <= 60; ++y) grid.set_cost({x, y}, PlanningGrid::kLethal);
  }
  const PlanResult detour = planner.plan(grid, start, goal);
  EXPECT_EQ(planner.roadmap_builds(), 2U);
  ASSERT_TRUE(detour.ok());
  EXPECT_EQ(detour.cells, VoronoiPlanner().plan(grid, start, goal).cells);
  for (const CellIndex c : detour.cells) EXPECT_FALSE(c.y == 60 && c.x >= 60 && c.x <= 99);

  // The same costs elsewhere in the map frame are another grid too.
  const PlanningGrid moved(grid.width(), grid.height(), grid.resolution_m(), {1.0, 0.0, 0.0});
  planner.roadmap_for(moved);
  EXPECT_EQ(planner.roadmap_builds(), 3U);
  planner.roadmap_for(moved);
  EXPECT_EQ(planner.roadmap_builds(), 3U);
}

TEST(VoronoiPlanner, ReducesALongCorridorToAFewWaypoints) {
  OccupancyGrid map = free_map(400, 30);
  fill(map, 0, 0, 399, 0, OccupancyGrid::kOccupied);
  fill(map, 0, 29, 399, 29, OccupancyGrid::kOccupied);
  const PlanningGrid grid = build(map);
  VoronoiPlanner planner;
  // Both ends off the centre line (y = 0.75 m): onto it, along it, off it.
  const PlanResult result = planner.plan(grid, {0.3, 0.55, 0.0}, {19.7, 0.95, 0.0});
  ASSERT_TRUE(result.ok());
  EXPECT_GT(result.cells.size(), 380U);
  EXPECT_LE(result.points_in_map.size(), 6U);
  for (std::size_t i = 1; i + 1 < result.points_in_map.size(); ++i) {
    EXPECT_NEAR(result.points_in_map[i].y, 0.75, 0.05);  // the inner waypoints are on the middle
  }
  expect_clear_waypoints(grid, result);
  // Straight onto the middle (row 14, y = 0.725 m), along it, straight off it to the goal.
  EXPECT_NEAR(result.length_m, 0.175 + 19.35 + 0.225, 0.01);
}

TEST(VoronoiWaypoints, NeverCutThroughBlockedCells) {
  // Cell centres around the corner of an inscribed block: with any tolerance, a chord from the
  // first to the last point would cross the block, so the corner is kept.
  PlanningGrid grid(20, 20, 0.1, {});
  for (int y = 5; y <= 14; ++y) {
    for (int x = 5; x <= 14; ++x) grid.set_cost({x, y}, PlanningGrid::kInscribed);
  }
  std::vector<geometry::Point2D> points;
  for (int x = 2; x <= 15; ++x) points.push_back(grid.cell_center({x, 4}));
  for (int y = 5; y <= 17; ++y) points.push_back(grid.cell_center({15, y}));
  const auto waypoints = reduce_to_waypoints(grid, points, 10.0);
  EXPECT_EQ(waypoints,
            (std::vector<geometry::Point2D>{grid.cell_center({2, 4}), grid.cell_center({15, 4}),
                                            grid.cell_center({15, 17})}));

  // A chord that grazes the block's corner cell: kept out too, whatever the tolerance.
  const std::vector<geometry::Point2D> diagonal{grid.cell_center({3, 4}), grid.cell_center({4, 4}),
                                                grid.cell_center({4, 3}), grid.cell_center({15, 4}),
                                                grid.cell_center({15, 15})};
  const auto cut = reduce_to_waypoints(grid, diagonal, 10.0);
  for (std::size_t i = 1; i < cut.size(); ++i) {
    EXPECT_TRUE(segment_is_clear(grid, cut[i - 1], cut[i], PlanningGrid::kMaxInflated)) << i;
  }
}

TEST(VoronoiWaypoints, KeepsTurnsLargerThanTheTolerance) {
  const PlanningGrid grid(40, 40, 0.1, {});
  std::vector<geometry::Point2D> points;
  for (int i = 0; i <= 30; ++i) points.push_back({0.05 + 0.1 * i, 0.05});  // collinear
  EXPECT_EQ(reduce_to_waypoints(grid, points, 0.0).size(), 2U);
  points[15].y += 0.04;  // a 4 cm bump
  EXPECT_EQ(reduce_to_waypoints(grid, points, 0.05).size(), 2U);
  const auto fine = reduce_to_waypoints(grid, points, 0.03);
  EXPECT_NE(std::find(fine.begin(), fine.end(), points[15]), fine.end());
  // Each kept segment is within the tolerance of the points it replaces.
  for (std::size_t i = 0; i < points.size(); ++i) {
    double nearest = kInf;
    for (std::size_t k = 1; k < fine.size(); ++k) {
      const geometry::Point2D a = fine[k - 1];
      const geometry::Point2D b = fine[k];
      const double t =
          std::clamp(((points[i].x - a.x) * (b.x - a.x) + (points[i].y - a.y) * (b.y - a.y)) /
                         ((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y)),
                     0.0, 1.0);
      nearest = std::min(nearest, std::hypot(points[i].x - (a.x + t * (b.x - a.x)),
                                             points[i].y - (a.y + t * (b.y - a.y))));
    }
    EXPECT_LE(nearest, 0.03 + 1e-9) << i;
  }
  EXPECT_EQ(reduce_to_waypoints(grid, std::vector<geometry::Point2D>{{0.1, 0.1}}, 0.05).size(), 1U);
  EXPECT_THROW(reduce_to_waypoints(grid, points, -0.1), std::invalid_argument);
}

TEST(VoronoiPlanner, RejectsBadOptions) {
  VoronoiPlannerOptions options;
  options.off_roadmap_factor = 0.5;  // the heuristic would overestimate
  EXPECT_THROW(VoronoiPlanner{options}, std::invalid_argument);
  options = {};
  options.waypoint_tolerance_m = -1.0;
  EXPECT_THROW(VoronoiPlanner{options}, std::invalid_argument);
  options = {};
  options.max_escape_distance_m = std::nan("");
  EXPECT_THROW(VoronoiPlanner{options}, std::invalid_argument);
  options = {};
  options.roadmap.min_passage_width_m = -0.1;
  EXPECT_THROW(VoronoiPlanner{options}, std::invalid_argument);
}

}  // namespace
}  // namespace mobot::planning
