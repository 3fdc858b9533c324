#include "core/planning/astar_planner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>
#include <random>
#include <utility>
#include <vector>

#include "core/planning/astar_planner.h"

namespace mobot::planning {
namespace {

using mapping::CellIndex;

constexpr double kRes = 0.1;
constexpr double kInf = std::numeric_limits<double>::infinity();

PlanningGrid make_grid(int width, int height) { return PlanningGrid(width, height, kRes, {}); }

geometry::Pose2D at(const PlanningGrid& grid, CellIndex cell) {
  const geometry::Point2D p = grid.cell_center(cell);
  return {p.x, p.y, 0.0};
}

// A random grid: mostly free, some inflation costs, some blocked cells.
PlanningGrid random_grid(std::mt19937& rng, int width, int height) {
  PlanningGrid grid = make_grid(width, height);
  std::uniform_int_distribution<int> kind(0, 9);
  std::uniform_int_distribution<int> band(1, 252);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const int k = kind(rng);
      std::uint8_t cost = PlanningGrid::kFree;
      if (k <= 1) cost = PlanningGrid::kLethal;
      if (k == 2) cost = PlanningGrid::kInscribed;
      if (k == 3 || k == 4) cost = static_cast<std::uint8_t>(band(rng));
      grid.set_cost({x, y}, cost);
    }
  }
  return grid;
}

bool step_allowed(const PlanningGrid& grid, CellIndex from, CellIndex to) {
  if (!grid.is_traversable(to)) return false;
  if (from.x != to.x && from.y != to.y) {
    return grid.is_traversable({to.x, from.y}) && grid.is_traversable({from.x, to.y});
  }
  return true;
}

double step_cost(const AStarPlanner& planner, const PlanningGrid& grid, CellIndex from,
                 CellIndex to) {
  const double length = (from.x != to.x && from.y != to.y) ? std::numbers::sqrt2 : 1.0;
  return kRes * length * planner.step_multiplier(grid.cost(to));
}

// Brute-force reference: Dijkstra over the same edges. reverse = distances *to* `source`.
std::vector<double> dijkstra(const AStarPlanner& planner, const PlanningGrid& grid,
                             CellIndex source, bool reverse) {
  std::vector<double> dist(grid.costs().size(), kInf);
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  dist[grid.index_of(source)] = 0.0;
  open.push({0.0, grid.index_of(source)});
  while (!open.empty()) {
    const auto [d, index] = open.top();
    open.pop();
    if (d > dist[index]) continue;
    const CellIndex cell = grid.cell_of(index);
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const CellIndex next{cell.x + dx, cell.y + dy};
        if ((dx == 0 && dy == 0) || !grid.contains(next)) continue;
        const CellIndex from = reverse ? next : cell;
        const CellIndex to = reverse ? cell : next;
        if (!grid.is_traversable(from) || !step_allowed(grid, from, to)) continue;
        const double nd = d + step_cost(planner, grid, from, to);
        if (nd < dist[grid.index_of(next)]) {
          dist[grid.index_of(next)] = nd;
          open.push({nd, grid.index_of(next)});
        }
      }
    }
  }
  return dist;
}

double path_cost(const AStarPlanner& planner, const PlanningGrid& grid,
                 const std::vector<CellIndex>& cells) {
  double cost = 0.0;
  for (std::size_t i = 1; i < cells.size(); ++i) {
    cost += step_cost(planner, grid, cells[i - 1], cells[i]);
  }
  return cost;
}

TEST(AStarPlanner, MatchesBruteForceDijkstraOnRandomGrids) {
  std::mt19937 rng(42);
  int compared = 0;
  int unreachable = 0;
  for (const double weight : {0.0, 3.0}) {
    AStarOptions options;
    options.cost_penalty_weight = weight;
    AStarPlanner planner(options);
    for (int trial = 0; trial < 150; ++trial) {
      const PlanningGrid grid = random_grid(rng, 14, 11);
      std::uniform_int_distribution<int> ux(0, 13);
      std::uniform_int_distribution<int> uy(0, 10);
      const CellIndex start{ux(rng), uy(rng)};
      const CellIndex goal{ux(rng), uy(rng)};
      if (!grid.is_traversable(start) || !grid.is_traversable(goal)) continue;
      const double reference = dijkstra(planner, grid, start, false)[grid.index_of(goal)];
      const PlanResult result = planner.plan(grid, at(grid, start), at(grid, goal));
      if (reference == kInf) {
        ++unreachable;
        ASSERT_FALSE(result.ok());
        EXPECT_EQ(*result.error, PlanError::kNoPath);
        continue;
      }
      ++compared;
      ASSERT_TRUE(result.ok()) << trial;
      EXPECT_NEAR(result.cost, reference, 1e-9) << trial;
      // The returned cells are a legal path whose cost is the reported one.
      ASSERT_EQ(result.cells.front(), start);
      ASSERT_EQ(result.cells.back(), goal);
      for (std::size_t i = 1; i < result.cells.size(); ++i) {
        const CellIndex a = result.cells[i - 1];
        const CellIndex b = result.cells[i];
        ASSERT_LE(std::max(std::abs(a.x - b.x), std::abs(a.y - b.y)), 1);
        ASSERT_TRUE(step_allowed(grid, a, b)) << "corner cut or blocked cell";
      }
      EXPECT_NEAR(path_cost(planner, grid, result.cells), result.cost, 1e-9);
    }
  }
  EXPECT_GT(compared, 100);  // the random grids really exercised the search
  EXPECT_GT(unreachable, 0);
}

TEST(AStarPlanner, OctileHeuristicIsAdmissible) {
  std::mt19937 rng(7);
  const AStarPlanner planner;
  int checked = 0;
  for (int trial = 0; trial < 20; ++trial) {
    PlanningGrid grid = random_grid(rng, 16, 16);
    const CellIndex goal{8, 8};
    grid.set_cost(goal, PlanningGrid::kFree);
    const std::vector<double> to_goal = dijkstra(planner, grid, goal, true);
    for (std::size_t i = 0; i < to_goal.size(); ++i) {
      if (to_goal[i] == kInf) continue;
      ++checked;
      const CellIndex c = grid.cell_of(i);
      const int dx = std::abs(c.x - goal.x);
      const int dy = std::abs(c.y - goal.y);
      const double h = kRes * (std::max(dx, dy) + (std::numbers::sqrt2 - 1.0) * std::min(dx, dy));
      EXPECT_LE(h, to_goal[i] + 1e-12);
    }
  }
  EXPECT_GT(checked, 1000);
  // Exact on an empty grid with no penalty.
  AStarOptions options;
  options.cost_penalty_weight = 0.0;
  AStarPlanner shortest(options);
  const PlanningGrid open = make_grid(30, 20);
  const PlanResult result = shortest.plan(open, at(open, {2, 3}), at(open, {25, 12}));
  ASSERT_TRUE(result.ok());
  EXPECT_NEAR(result.cost, kRes * (23 + (std::numbers::sqrt2 - 1.0) * 9), 1e-9);
  // With a consistent heuristic and open ground the search only expands cells near the line.
  EXPECT_LT(result.expanded_cells, 200U);
}

TEST(AStarPlanner, DoesNotCutCorners) {
  PlanningGrid grid = make_grid(3, 3);
  grid.set_cost({1, 0}, PlanningGrid::kLethal);
  AStarPlanner planner;
  const PlanResult result = planner.plan(grid, at(grid, {0, 0}), at(grid, {1, 1}));
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result.cells, (std::vector<CellIndex>{{0, 0}, {0, 1}, {1, 1}}));

  grid.set_cost({0, 1}, PlanningGrid::kInscribed);  // now the only way is the diagonal gap
  const PlanResult blocked = planner.plan(grid, at(grid, {0, 0}), at(grid, {1, 1}));
  ASSERT_FALSE(blocked.ok());
  EXPECT_EQ(*blocked.error, PlanError::kNoPath);
}

TEST(AStarPlanner, TradesLengthForClearance) {
  // Around a block: the shorter route below runs through a high-cost band, the longer one above
  // is free. Without the penalty A* takes the short one, with it the clear one.
  PlanningGrid grid = make_grid(21, 10);
  for (int x = 3; x <= 17; ++x) {
    for (int y = 3; y <= 6; ++y) grid.set_cost({x, y}, PlanningGrid::kLethal);
    for (int y = 0; y <= 2; ++y) grid.set_cost({x, y}, 200);
  }
  const auto below = [](const PlanResult& r) {
    return std::any_of(r.cells.begin(), r.cells.end(), [](CellIndex c) { return c.y <= 2; });
  };
  AStarPlanner planner;
  const PlanResult clear = planner.plan(grid, at(grid, {1, 4}), at(grid, {19, 4}));
  ASSERT_TRUE(clear.ok());
  EXPECT_FALSE(below(clear));

  AStarOptions options;
  options.cost_penalty_weight = 0.0;
  AStarPlanner shortest(options);
  const PlanResult direct = shortest.plan(grid, at(grid, {1, 4}), at(grid, {19, 4}));
  ASSERT_TRUE(direct.ok());
  EXPECT_TRUE(below(direct));
  EXPECT_LT(direct.length_m, clear.length_m);
}

TEST(AStarPlanner, ReturnsWorldPointsEndingExactlyAtStartAndGoal) {
  const PlanningGrid grid(50, 50, 0.05, {-1.0, -1.0, 0.0});
  AStarPlanner planner;
  const PlanResult result = planner.plan(grid, {-0.93, -0.91, 0.2}, {0.97, 0.52, 1.0});
  ASSERT_TRUE(result.ok());
  ASSERT_EQ(result.points_in_map.size(), result.cells.size());
  EXPECT_EQ(result.points_in_map.front(), (geometry::Point2D{-0.93, -0.91}));
  EXPECT_EQ(result.points_in_map.back(), (geometry::Point2D{0.97, 0.52}));
  EXPECT_EQ(result.points_in_map[1], grid.cell_center(result.cells[1]));
  EXPECT_GT(result.length_m, std::hypot(1.9, 1.43) - 1e-9);
  EXPECT_LT(result.length_m, std::hypot(1.9, 1.43) * 1.1);

  const PlanResult same_cell = planner.plan(grid, {0.01, 0.01, 0.0}, {0.02, 0.03, 0.0});
  ASSERT_TRUE(same_cell.ok());
  EXPECT_EQ(same_cell.cells.size(), 1U);
  EXPECT_EQ(same_cell.points_in_map.size(), 2U);
}

TEST(AStarPlanner, StartInInflationEscapesToTheNearestFreeCell) {
  // A wall at x = 10 inflated: x 7..9 inscribed, robot at x = 8 touching it.
  PlanningGrid grid = make_grid(20, 10);
  for (int y = 0; y < 10; ++y) {
    grid.set_cost({10, y}, PlanningGrid::kLethal);
    for (int x = 7; x <= 9; ++x) grid.set_cost({x, y}, PlanningGrid::kInscribed);
    for (int x = 11; x <= 13; ++x) grid.set_cost({x, y}, PlanningGrid::kInscribed);
  }
  AStarPlanner planner;
  const PlanResult result = planner.plan(grid, at(grid, {8, 5}), at(grid, {2, 5}));
  ASSERT_TRUE(result.ok());
  EXPECT_TRUE(result.start_escaped);
  EXPECT_EQ(result.cells.front(), (CellIndex{8, 5}));
  EXPECT_EQ(result.cells[1], (CellIndex{7, 5}));
  EXPECT_EQ(result.cells[2],
            (CellIndex{6, 5}));  // the first free cell: straight away from the wall
  EXPECT_EQ(result.cells.back(), (CellIndex{2, 5}));
  EXPECT_NEAR(result.cost, 0.6, 1e-9);
  // After the escape the path stays in free space.
  for (std::size_t i = 2; i < result.cells.size(); ++i)
    EXPECT_TRUE(grid.is_traversable(result.cells[i]));

  // The escape never crosses the wall itself, even when the other side is as near.
  const PlanResult across = planner.plan(grid, at(grid, {9, 5}), at(grid, {18, 5}));
  ASSERT_FALSE(across.ok());
  EXPECT_EQ(*across.error, PlanError::kNoPath);

  // Too deep in an obstacle: refused.
  AStarOptions options;
  options.max_escape_distance_m = 0.15;
  AStarPlanner strict(options);
  EXPECT_EQ(strict.plan(grid, at(grid, {9, 5}), at(grid, {2, 5})).error,
            PlanError::kStartInObstacle);
}

TEST(AStarPlanner, StartInsideALethalCellEscapesThroughIt) {
  PlanningGrid grid = make_grid(10, 10);
  grid.set_cost({5, 5}, PlanningGrid::kLethal);
  AStarPlanner planner;
  const PlanResult result = planner.plan(grid, at(grid, {5, 5}), at(grid, {1, 1}));
  ASSERT_TRUE(result.ok());
  EXPECT_TRUE(result.start_escaped);
  EXPECT_EQ(result.cells.front(), (CellIndex{5, 5}));
}

TEST(AStarPlanner, FindsItsWayThroughAMaze) {
  // A serpentine: walls with alternating gaps force a path of about 5 x the width.
  PlanningGrid grid = make_grid(40, 41);
  for (int wall = 1; wall <= 9; ++wall) {
    const int y = wall * 4;
    for (int x = 0; x < 40; ++x) grid.set_cost({x, y}, PlanningGrid::kLethal);
    grid.set_cost({wall % 2 == 1 ? 39 : 0, y}, PlanningGrid::kFree);
  }
  AStarPlanner planner;
  const PlanResult result = planner.plan(grid, at(grid, {0, 0}), at(grid, {0, 40}));
  ASSERT_TRUE(result.ok());
  EXPECT_GT(result.length_m, 9 * 3.5);
  const std::vector<double> reference = dijkstra(planner, grid, {0, 0}, false);
  EXPECT_NEAR(result.cost, reference[grid.index_of({0, 40})], 1e-9);
}

// A grid of mostly free cells: `blocked` of them lethal or inscribed, `banded` in the inflation
// band. Sparse obstacles leave long runs of equal f, which the open list must still order exactly.
PlanningGrid sparse_grid(std::mt19937& rng, int width, int height, double blocked, double banded) {
  PlanningGrid grid = make_grid(width, height);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> band(1, 252);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double r = u(rng);
      if (r < blocked) {
        grid.set_cost({x, y}, r < blocked / 2 ? PlanningGrid::kLethal : PlanningGrid::kInscribed);
      } else if (r < blocked + banded) {
        grid.set_cost({x, y}, static_cast<std::uint8_t>(band(rng)));
      }
    }
  }
  return grid;
}

// The result is a legal path from start to goal whose cost is the Dijkstra optimum (to 1e-9
// relative) and the sum of its steps.
void expect_optimal(const AStarPlanner& planner, const PlanningGrid& grid, CellIndex start,
                    CellIndex goal, const PlanResult& result, double reference) {
  ASSERT_TRUE(result.ok());
  const double tolerance = 1e-9 * std::max(1.0, reference);
  EXPECT_NEAR(result.cost, reference, tolerance);
  ASSERT_EQ(result.cells.front(), start);
  ASSERT_EQ(result.cells.back(), goal);
  for (std::size_t i = 1; i < result.cells.size(); ++i) {
    const CellIndex a = result.cells[i - 1];
    const CellIndex b = result.cells[i];
    ASSERT_LE(std::max(std::abs(a.x - b.x), std::abs(a.y - b.y)), 1);
    ASSERT_TRUE(step_allowed(grid, a, b)) << "corner cut or blocked cell";
  }
  EXPECT_NEAR(path_cost(planner, grid, result.cells), result.cost, tolerance);
}

TEST(AStarPlanner, MatchesDijkstraOnLargerGridsAndCostWeights) {
  // Larger grids than the brute-force test, open and cluttered, with and without cost bands, and
  // cost weights up to 1e6, where the open list's buckets widen to keep their count bounded (to
  // hundreds of cells at 1e6, so a search runs mostly inside one bucket, on its exact order).
  std::mt19937 rng(2024);
  int compared = 0;
  for (const double weight : {0.0, 3.0, 40.0, 1e4, 1e6}) {
    AStarOptions options;
    options.cost_penalty_weight = weight;
    AStarPlanner planner(options);
    for (const auto& [blocked, banded] : {std::pair{0.02, 0.0}, std::pair{0.25, 0.0},
                                          std::pair{0.02, 0.05}, std::pair{0.25, 0.3}}) {
      const PlanningGrid grid = sparse_grid(rng, 70, 45, blocked, banded);
      std::uniform_int_distribution<int> ux(0, 69);
      std::uniform_int_distribution<int> uy(0, 44);
      for (int trial = 0; trial < 15; ++trial) {
        const CellIndex start{ux(rng), uy(rng)};
        const CellIndex goal{ux(rng), uy(rng)};
        if (!grid.is_traversable(start) || !grid.is_traversable(goal)) continue;
        const double reference = dijkstra(planner, grid, start, false)[grid.index_of(goal)];
        const PlanResult result = planner.plan(grid, at(grid, start), at(grid, goal));
        if (reference == kInf) {
          ASSERT_FALSE(result.ok());
          EXPECT_EQ(*result.error, PlanError::kNoPath);
          continue;
        }
        ++compared;
        expect_optimal(planner, grid, start, goal, result, reference);
      }
    }
  }
  EXPECT_GT(compared, 150);
}

TEST(AStarPlanner, ReachesEveryCellAtItsOptimalCost) {
  // Every reachable cell as the goal: each search must pop its goal at the optimal g, a check on
  // the open list's order that one goal per grid rarely exposes (most order slips are masked by an
  // equally cheap detour). Weight 1e4 makes the buckets a few cells wide.
  std::mt19937 rng(99);
  for (const double weight : {3.0, 1e4}) {
    AStarOptions options;
    options.cost_penalty_weight = weight;
    AStarPlanner planner(options);
    for (const double blocked : {0.02, 0.25}) {
      PlanningGrid grid = sparse_grid(rng, 40, 30, blocked, 0.05);
      const CellIndex start{20, 15};
      grid.set_cost(start, PlanningGrid::kFree);
      const std::vector<double> reference = dijkstra(planner, grid, start, false);
      int reached = 0;
      for (std::size_t i = 0; i < reference.size(); ++i) {
        const CellIndex goal = grid.cell_of(i);
        if (reference[i] == kInf || !grid.is_traversable(goal)) continue;
        const PlanResult result = planner.plan(grid, at(grid, start), at(grid, goal));
        ASSERT_TRUE(result.ok()) << goal.x << "," << goal.y;
        ASSERT_NEAR(result.cost, reference[i], 1e-9 * std::max(1.0, reference[i]))
            << goal.x << "," << goal.y << " weight " << weight;
        ++reached;
      }
      EXPECT_GT(reached, 500);
    }
  }
}

TEST(AStarPlanner, OpenGroundAtAnyAngleStaysOptimal) {
  // Free space: whole regions share one f, the case where the tie-break on h matters and the
  // open list sees most pushes land in the bucket being popped from.
  const PlanningGrid grid = make_grid(90, 60);
  AStarOptions options;
  options.cost_penalty_weight = 0.0;
  AStarPlanner planner(options);
  const CellIndex start{3, 4};
  const std::vector<double> from_start = dijkstra(planner, grid, start, false);
  for (const CellIndex goal : {CellIndex{89, 59}, CellIndex{89, 4}, CellIndex{60, 59},
                               CellIndex{89, 40}, CellIndex{20, 55}, CellIndex{3, 5}}) {
    const PlanResult result = planner.plan(grid, at(grid, start), at(grid, goal));
    expect_optimal(planner, grid, start, goal, result, from_start[grid.index_of(goal)]);
    // The tie-break keeps the search on the band of optimal paths.
    EXPECT_LT(result.expanded_cells, 30U * result.cells.size()) << goal.x << "," << goal.y;
  }
}

TEST(AStarPlanner, ReusedPlannerGivesTheSameResultsAsAFreshOne) {
  // One planner across 5000 searches (more than the 4095 its stamps' search numbers hold, so they
  // wrap and are reset), grids of two shapes, resolutions and cell counts, searches that stop at
  // the goal with nodes still open and searches that fail: every result equals a new planner's.
  std::mt19937 rng(5);
  const PlanningGrid a = random_grid(rng, 20, 15);
  PlanningGrid b(20, 15, 0.05, {});  // as a, at another resolution
  b.mutable_costs() = random_grid(rng, 20, 15).costs();
  const PlanningGrid c = random_grid(rng, 15, 20);  // as many cells (state kept), another shape
  const PlanningGrid d = random_grid(rng, 33, 9);   // another cell count: state reallocated
  const std::vector<const PlanningGrid*> grids{&a, &b, &c};
  AStarPlanner reused;
  int succeeded = 0;
  int failed = 0;
  for (int i = 0; succeeded + failed < 5000; ++i) {
    // The other cell count once, late (each change of cell count resets the stamps).
    const PlanningGrid& grid =
        succeeded + failed == 4500 ? d : *grids[static_cast<std::size_t>(i) % grids.size()];
    std::uniform_int_distribution<int> ux(0, grid.width() - 1);
    std::uniform_int_distribution<int> uy(0, grid.height() - 1);
    const CellIndex start{ux(rng), uy(rng)};
    const CellIndex goal{ux(rng), uy(rng)};
    if (!grid.is_traversable(start) || !grid.is_traversable(goal)) continue;  // searches only
    const PlanResult result = reused.plan(grid, at(grid, start), at(grid, goal));
    const PlanResult fresh = AStarPlanner().plan(grid, at(grid, start), at(grid, goal));
    ASSERT_EQ(result.ok(), fresh.ok()) << i;
    if (!result.ok()) {
      EXPECT_EQ(*result.error, *fresh.error) << i;
      ++failed;
      continue;
    }
    ++succeeded;
    ASSERT_EQ(result.cost, fresh.cost) << i;
    ASSERT_EQ(result.cells, fresh.cells) << i;
    ASSERT_EQ(result.expanded_cells, fresh.expanded_cells) << i;
  }
  EXPECT_GT(succeeded, 2000);
  EXPECT_GT(failed, 100);  // kNoPath
}

TEST(AStarPlanner, RejectsBadOptions) {
  AStarOptions options;
  options.cost_penalty_weight = -1.0;
  EXPECT_THROW(AStarPlanner{options}, std::invalid_argument);
}

}  // namespace
}  // namespace mobot::planning
