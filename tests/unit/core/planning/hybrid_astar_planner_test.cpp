#include "core/planning/hybrid_astar_planner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "core/planning/planning_grid_builder.h"
#include "tests/unit/core/planning/planning_test_maps.h"

namespace mobot::planning {
namespace {

using geometry::Point2D;
using geometry::Pose2D;
using test_maps::fill;
using test_maps::free_map;
using test_maps::outline;

constexpr double kPi = std::numbers::pi;
constexpr double kRadius = 1.844;  // R3: wheelbase 1.844 m, steering pi / 4
constexpr std::uint8_t kWall = mapping::OccupancyGrid::kOccupied;

// The tricycles' planning grid: deploy/config/tricycle_*.yaml inflates by 0.8 m and lets the
// cost fall off over 1.5 m beyond.
PlanningGrid tricycle_grid(const mapping::OccupancyGrid& map) {
  PlanningGridOptions options;
  options.inscribed_radius_m = 0.8;
  options.inflation_margin_m = 1.5;
  options.cost_scaling_per_m = 3.0;
  return PlanningGridBuilder(options).build(map);
}

// Cells of the test maps are 0.05 m: metres to cells.
int cells(double metres) { return static_cast<int>(std::lround(metres / test_maps::kRes)); }

void wall(mapping::OccupancyGrid& map, double x0, double y0, double x1, double y1) {
  fill(map, cells(x0), cells(y0), cells(x1) - 1, cells(y1) - 1, kWall);
}

// A walled yard of width x height metres.
mapping::OccupancyGrid yard(double width_m, double height_m) {
  mapping::OccupancyGrid map = free_map(cells(width_m), cells(height_m));
  outline(map);
  return map;
}

// The largest curvature of the polyline, from the circle through each three consecutive points.
double max_curvature(const std::vector<Point2D>& p) {
  double worst = 0.0;
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    const double a = std::hypot(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y);
    const double b = std::hypot(p[i + 1].x - p[i].x, p[i + 1].y - p[i].y);
    const double c = std::hypot(p[i + 1].x - p[i - 1].x, p[i + 1].y - p[i - 1].y);
    const double cross = std::abs((p[i].x - p[i - 1].x) * (p[i + 1].y - p[i - 1].y) -
                                  (p[i].y - p[i - 1].y) * (p[i + 1].x - p[i - 1].x));
    worst = std::max(worst, 2.0 * cross / (a * b * c));
  }
  return worst;
}

// Whether R3's body (2.64 x 1.2 m, reaching 2.24 m ahead of and 0.4 m behind the rear axle)
// overlaps a lethal cell or leaves the grid at this pose: the body's area sampled every 2.5 cm.
bool body_hits_obstacle(const PlanningGrid& grid, const Pose2D& pose) {
  const double c = std::cos(pose.theta);
  const double s = std::sin(pose.theta);
  for (double u = -0.4; u <= 2.24 + 1e-9; u += 0.025) {
    for (double v = -0.6; v <= 0.6 + 1e-9; v += 0.025) {
      const auto cell = grid.cell_at({pose.x + c * u - s * v, pose.y + s * u + c * v});
      if (!cell || grid.cost(*cell) == PlanningGrid::kLethal) return true;
    }
  }
  return false;
}

// The path's pose at each point, the heading along the chord to the next point (the last takes
// the previous chord's).
std::vector<Pose2D> poses_along(const std::vector<Point2D>& p) {
  std::vector<Pose2D> poses;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::size_t a = i + 1 < p.size() ? i : i - 1;
    poses.push_back({p[i].x, p[i].y, std::atan2(p[a + 1].y - p[a].y, p[a + 1].x - p[a].x)});
  }
  return poses;
}

// What every successful plan must satisfy: ends exactly at start and goal, points close together,
// curvature within the car's, the body clear of obstacles everywhere, and cells that are the
// 8-connected trace of the points.
void expect_drivable(const HybridAStarPlanner& planner, const PlanningGrid& grid,
                     const Pose2D& start, const Pose2D& goal, const PlanResult& result) {
  ASSERT_TRUE(result.ok()) << error_code(*result.error);
  const auto& points = result.points_in_map;
  ASSERT_GE(points.size(), 2u);
  EXPECT_EQ(points.front(), (Point2D{start.x, start.y}));
  EXPECT_EQ(points.back(), (Point2D{goal.x, goal.y}));
  double length = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) {
    const double step = std::hypot(points[i].x - points[i - 1].x, points[i].y - points[i - 1].y);
    EXPECT_LE(step, planner.options().path_step_m + 1e-9);
    EXPECT_GT(step, 0.0);
    length += step;
  }
  EXPECT_NEAR(result.length_m, length, 1e-9);
  EXPECT_LE(max_curvature(points), 1.0 / planner.options().min_turning_radius_m + 1e-6);
  // The first chord leaves along the start heading, turning at most as a full-lock arc does over
  // one step.
  const double first = std::atan2(points[1].y - points[0].y, points[1].x - points[0].x);
  EXPECT_LE(std::abs(geometry::wrap_angle(first - start.theta)),
            0.5 * planner.options().path_step_m / planner.options().min_turning_radius_m + 1e-9);
  // The body never overlaps an obstacle, and past an escape every check point is off the
  // inscribed band (the heading taken along the chords, so a little off the arc's).
  const std::vector<Point2D> check_points = planner.check_points(grid.resolution_m());
  const std::vector<Pose2D> poses = poses_along(points);
  double travelled = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Pose2D& pose = poses[i];
    ASSERT_FALSE(body_hits_obstacle(grid, pose)) << pose.x << ", " << pose.y << ", " << pose.theta;
    if (i > 0)
      travelled += std::hypot(points[i].x - points[i - 1].x, points[i].y - points[i - 1].y);
    if (result.start_escaped && travelled <= planner.options().max_escape_distance_m) continue;
    for (const Point2D& p : check_points) {
      const Point2D q{pose.x + std::cos(pose.theta) * p.x - std::sin(pose.theta) * p.y,
                      pose.y + std::sin(pose.theta) * p.x + std::cos(pose.theta) * p.y};
      ASSERT_TRUE(grid.is_traversable(*grid.cell_at(q)))
          << "point " << i << " of " << points.size();
    }
  }
  ASSERT_FALSE(result.cells.empty());
  EXPECT_EQ(result.cells.front(), *grid.cell_at(points.front()));
  EXPECT_EQ(result.cells.back(), *grid.cell_at(points.back()));
  for (std::size_t i = 1; i < result.cells.size(); ++i) {
    const auto a = result.cells[i - 1];
    const auto b = result.cells[i];
    EXPECT_FALSE(a == b);
    EXPECT_LE(std::max(std::abs(a.x - b.x), std::abs(a.y - b.y)), 1);
  }
  for (const Point2D& p : points) {
    EXPECT_NE(std::find(result.cells.begin(), result.cells.end(), *grid.cell_at(p)),
              result.cells.end());
  }
}

TEST(HybridAStarPlanner, DefaultsAreTheTricycles) {
  const HybridAStarPlanner planner;
  EXPECT_EQ(planner.name(), "hybrid_astar");
  EXPECT_FALSE(planner.route_may_be_smoothed());
  EXPECT_DOUBLE_EQ(planner.options().min_turning_radius_m, kRadius);
  // 0.5 m rounded to three 5 degree bins of a full-lock arc.
  EXPECT_NEAR(planner.primitive_length_m(), 3 * (kPi / 36) * kRadius, 1e-12);
}

// A planning grid with the same costs as `grid` and its origin moved to `origin`.
PlanningGrid moved(const PlanningGrid& grid, const Pose2D& origin) {
  PlanningGrid out(grid.width(), grid.height(), grid.resolution_m(), origin);
  out.mutable_costs() = grid.costs();
  return out;
}

TEST(HybridAStarPlanner, GoalBehindInOpenSpaceIsDrivable) {
  // A 20 m walled yard centred on the map origin; the goal 3 m behind the robot.
  const PlanningGrid grid = moved(tricycle_grid(yard(20.0, 20.0)), {-10.0, -10.0, 0.0});
  HybridAStarPlanner planner;
  const Pose2D start{0.0, 0.0, 0.0};
  const Pose2D goal{-3.0, 0.0, 0.0};
  const PlanResult result = planner.plan(grid, start, goal);
  expect_drivable(planner, grid, start, goal, result);
  // A car cannot drive 3 m backwards: it loops round, at least half a turn of radius R.
  EXPECT_GT(result.length_m, kPi * kRadius);
  EXPECT_LT(result.length_m, 20.0);
  EXPECT_FALSE(result.start_escaped);
}

TEST(HybridAStarPlanner, LeavesAlongTheStartHeadingInAnyDirection) {
  // The grid's own frame rotated and shifted in the map: headings and cells must follow it.
  const PlanningGrid grid = tricycle_grid(yard(20.0, 20.0));
  const PlanningGrid turned = moved(grid, {-3.0, 2.0, 0.4});
  HybridAStarPlanner planner;
  for (const double heading : {0.0, 1.0, 2.5, -2.0, kPi}) {
    for (const PlanningGrid* g : {&grid, &turned}) {
      // The yard's centre and a goal 4 m off it, in the map frame.
      const Point2D centre = g->cell_center({200, 200});
      const Pose2D start{centre.x, centre.y, heading};
      const Pose2D goal{centre.x + 4.0, centre.y - 2.0, 0.0};
      const PlanResult result = planner.plan(*g, start, goal);
      expect_drivable(planner, *g, start, goal, result);
    }
  }
}

TEST(HybridAStarPlanner, HoldsTheGoalHeadingWhenAsked) {
  const PlanningGrid grid = tricycle_grid(yard(24.0, 20.0));
  HybridAStarOptions options;
  options.goal_heading_tolerance_rad = 0.05;
  HybridAStarPlanner planner(options);
  const Pose2D start{6.0, 10.0, 0.0};
  for (const double goal_heading : {kPi / 2, kPi, -kPi / 2, 0.0}) {
    const Pose2D goal{16.0, 12.0, goal_heading};
    const PlanResult result = planner.plan(grid, start, goal);
    expect_drivable(planner, grid, start, goal, result);
    const auto& p = result.points_in_map;
    const double last = std::atan2(p.back().y - p[p.size() - 2].y, p.back().x - p[p.size() - 2].x);
    EXPECT_LE(std::abs(geometry::wrap_angle(last - goal_heading)), 0.05 + 0.03) << goal_heading;
  }
}

// The heading of the path's last chord: how the body arrives.
double arrival_heading(const PlanResult& result) {
  const auto& p = result.points_in_map;
  return std::atan2(p.back().y - p[p.size() - 2].y, p.back().x - p[p.size() - 2].x);
}

// A goal 3.45 m short of a wall, straight ahead of the start: the body fits there nose to the
// wall (2.24 m ahead of the rear axle, 0.8 m of inflation), but a car that cannot reverse and
// turns no tighter than 1.844 m could not leave. It arrives at a heading it can leave by.
TEST(HybridAStarPlanner, AFreeHeadingGoalIsNotReachedWhereTheBodyCannotLeave) {
  const PlanningGrid grid = tricycle_grid(yard(20.0, 20.0));
  const Pose2D start{10.0, 6.0, kPi / 2};
  const Pose2D goal{10.0, 16.5, 0.0};  // heading free (the default tolerance)

  HybridAStarOptions trapping;
  trapping.keep_way_out = false;
  HybridAStarPlanner straight_in(trapping);
  const PlanResult trapped = straight_in.plan(grid, start, goal);
  expect_drivable(straight_in, grid, start, goal, trapped);
  ASSERT_NEAR(arrival_heading(trapped), kPi / 2, 1e-6) << "the shortest way drives straight in";
  const PlanResult stuck =
      straight_in.plan(grid, {goal.x, goal.y, arrival_heading(trapped)}, start);
  ASSERT_FALSE(stuck.ok()) << "the test's trap is not one";
  EXPECT_EQ(*stuck.error, PlanError::kNoPath);

  HybridAStarPlanner planner;
  const PlanResult result = planner.plan(grid, start, goal);
  expect_drivable(planner, grid, start, goal, result);
  const Pose2D arrived{goal.x, goal.y, arrival_heading(result)};
  const PlanResult back = planner.plan(grid, arrived, start);
  expect_drivable(planner, grid, arrived, start, back);
}

// A serpentine for the tricycle: 30 x 24 m, two 20 m walls from alternate sides leave 10 m gaps,
// so the way from the bottom-left to the top-left runs east, round the first wall's end, west,
// and round the second: two U-turns, each in an 8 m wide lane.
mapping::OccupancyGrid serpentine() {
  mapping::OccupancyGrid map = yard(30.0, 24.0);
  wall(map, 0.0, 8.0, 20.0, 8.4);
  wall(map, 10.0, 16.0, 30.0, 16.4);
  return map;
}

TEST(HybridAStarPlanner, FindsTheWayThroughASerpentine) {
  const PlanningGrid grid = tricycle_grid(serpentine());
  HybridAStarPlanner planner;
  const Pose2D start{3.0, 4.0, 0.0};
  const Pose2D goal{4.0, 20.0, 0.0};
  const PlanResult result = planner.plan(grid, start, goal);
  expect_drivable(planner, grid, start, goal, result);
  // East to the first gap, back west under the second wall: at least 2 x 15 m.
  EXPECT_GT(result.length_m, 30.0);
  // The grid heuristic leads it round the walls instead of filling the lanes with states.
  EXPECT_LT(result.expanded_cells, 20000u);
}

// A 3.6 m wide lane running east with a 2 m wide dead-end branch going north from its middle:
// the branch is wide enough for the robot's centre (a grid planner finds the way: 0.4 m of it
// is beyond the 0.8 m inflation) but the 2.64 m body turning no tighter than 1.844 m cannot get
// in.
mapping::OccupancyGrid lane_with_narrow_branch() {
  mapping::OccupancyGrid map = free_map(cells(24.0), cells(12.0));
  fill(map, 0, 0, map.width() - 1, map.height() - 1, kWall);
  fill(map, cells(1.0), cells(1.0), cells(23.0) - 1, cells(4.6) - 1, mapping::OccupancyGrid::kFree);
  fill(map, cells(11.0), cells(4.6), cells(13.0) - 1, cells(11.0) - 1,
       mapping::OccupancyGrid::kFree);
  return map;
}

TEST(HybridAStarPlanner, ABranchTooNarrowToTurnIntoIsNoPathInBoundedTime) {
  const PlanningGrid grid = tricycle_grid(lane_with_narrow_branch());
  const Pose2D start{3.0, 2.8, 0.0};
  const Pose2D goal{12.0, 9.0, 0.0};
  // The robot's centre fits: the holonomic search finds the branch.
  const auto goal_cell = *grid.cell_at({goal.x, goal.y});
  ASSERT_TRUE(grid.is_traversable(goal_cell));
  HybridAStarOptions options;
  options.max_expansions = 20000;
  HybridAStarPlanner planner(options);
  const PlanResult result = planner.plan(grid, start, goal);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(*result.error, PlanError::kNoPath);
  EXPECT_LE(result.expanded_cells, options.max_expansions);
  EXPECT_TRUE(result.points_in_map.empty());
  EXPECT_TRUE(result.cells.empty());

  // Widen the branch to 5 m and the body drives in; but it could not turn round at the dead end
  // to come out again, so with keep_way_out (the default) the goal is refused.
  mapping::OccupancyGrid wide = lane_with_narrow_branch();
  fill(wide, cells(9.5), cells(4.6), cells(14.5) - 1, cells(11.0) - 1,
       mapping::OccupancyGrid::kFree);
  const PlanningGrid wide_grid = tricycle_grid(wide);
  const PlanResult trap = planner.plan(wide_grid, start, goal);
  ASSERT_FALSE(trap.ok());
  EXPECT_EQ(*trap.error, PlanError::kNoPath);
  options.keep_way_out = false;
  HybridAStarPlanner one_way(options);
  const PlanResult in = one_way.plan(wide_grid, start, goal);
  expect_drivable(one_way, wide_grid, start, goal, in);
}

TEST(HybridAStarPlanner, ReportsBadInputs) {
  mapping::OccupancyGrid map = yard(20.0, 20.0);
  wall(map, 12.0, 0.0, 12.4, 20.0);  // cuts the yard in two
  wall(map, 5.0, 14.0, 6.0, 15.0);   // a post
  const PlanningGrid grid = tricycle_grid(map);
  HybridAStarPlanner planner;
  const Pose2D start{3.0, 5.0, 0.0};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto error_of = [&](const Pose2D& s, const Pose2D& g) {
    const PlanResult r = planner.plan(grid, s, g);
    EXPECT_TRUE(r.points_in_map.empty());
    EXPECT_TRUE(r.cells.empty());
    return r.error;
  };
  EXPECT_EQ(error_of({nan, 5.0, 0.0}, {8.0, 5.0, 0.0}), PlanError::kInvalidPose);
  EXPECT_EQ(error_of(start, {8.0, 5.0, nan}), PlanError::kInvalidPose);
  EXPECT_EQ(error_of(start, {8.0, std::numeric_limits<double>::infinity(), 0.0}),
            PlanError::kInvalidPose);
  EXPECT_EQ(error_of({-1.0, 5.0, 0.0}, {8.0, 5.0, 0.0}), PlanError::kStartOutsideMap);
  EXPECT_EQ(error_of(start, {8.0, 25.0, 0.0}), PlanError::kGoalOutsideMap);
  EXPECT_EQ(error_of(start, {5.5, 14.5, 0.0}), PlanError::kGoalInObstacle);  // on the post
  EXPECT_EQ(error_of(start, {12.2, 5.0, 0.0}), PlanError::kGoalInObstacle);  // on the wall
  EXPECT_EQ(error_of(start, {5.5, 13.3, 0.0}), PlanError::kGoalInObstacle);  // inscribed
  EXPECT_EQ(error_of({5.5, 14.5, 0.0}, {8.0, 5.0, 0.0}), PlanError::kStartInObstacle);
  EXPECT_EQ(planner.plan(PlanningGrid(), start, {8.0, 5.0, 0.0}).error, PlanError::kNoMap);
  // Beyond the wall: the grid heuristic finds no way and the search does not start.
  const PlanResult beyond = planner.plan(grid, start, {16.0, 10.0, 0.0});
  EXPECT_EQ(beyond.error, PlanError::kNoPath);
  EXPECT_EQ(beyond.expanded_cells, 0u);
}

TEST(HybridAStarPlanner, AGoalWhereTheBodyFitsNowhereIsInAnObstacle) {
  // A 2 m square pocket: the centre's cell is traversable, but the 2.64 m body fits at no
  // heading.
  mapping::OccupancyGrid map = yard(20.0, 20.0);
  wall(map, 8.0, 8.0, 14.0, 14.0);
  fill(map, cells(10.0), cells(10.0), cells(12.0) - 1, cells(12.0) - 1,
       mapping::OccupancyGrid::kFree);
  const PlanningGrid grid = tricycle_grid(map);
  const Pose2D goal{11.0, 11.0, 0.0};
  ASSERT_TRUE(grid.is_traversable(*grid.cell_at({goal.x, goal.y})));
  HybridAStarPlanner planner;
  EXPECT_EQ(planner.plan(grid, {3.0, 3.0, 0.0}, goal).error, PlanError::kGoalInObstacle);
}

TEST(HybridAStarPlanner, AStartTouchingTheInflationDrivesOut) {
  // The robot heads east along a wall with its body in the inscribed band (its centreline 0.7 m
  // from the wall, the band reaching 0.8 m): it may drive on, and the rest of the path is clear.
  mapping::OccupancyGrid map = yard(30.0, 20.0);
  wall(map, 0.0, 12.0, 30.0, 12.4);
  const PlanningGrid grid = tricycle_grid(map);
  const Pose2D start{4.0, 11.3, 0.0};
  HybridAStarPlanner planner;
  const Pose2D goal{18.0, 6.0, 0.0};
  const PlanResult result = planner.plan(grid, start, goal);
  expect_drivable(planner, grid, start, goal, result);
  EXPECT_TRUE(result.start_escaped);

  // With no escape allowed it is refused.
  HybridAStarOptions strict_options;
  strict_options.max_escape_distance_m = 0.0;
  HybridAStarPlanner strict(strict_options);
  EXPECT_EQ(strict.plan(grid, start, goal).error, PlanError::kStartInObstacle);

  // Facing the wall, 0.5 m of driving cannot clear the body: no clear pose is ever reached.
  const PlanResult facing = planner.plan(grid, {4.0, 10.0, kPi / 2}, goal);
  EXPECT_EQ(facing.error, PlanError::kStartInObstacle);
}

TEST(HybridAStarPlanner, AGoalInTheStartCellIsATwoPointPath) {
  const PlanningGrid grid = tricycle_grid(yard(20.0, 20.0));
  HybridAStarPlanner planner;
  const PlanResult result = planner.plan(grid, {10.01, 10.01, 0.3}, {10.02, 10.03, 2.0});
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result.points_in_map.size(), 2u);
  EXPECT_EQ(result.cells.size(), 1u);
}

TEST(HybridAStarPlanner, CheckPointsCoverTheBody) {
  for (const double cover : {0.3, 0.63, 1.0}) {
    const std::vector<Point2D> points = footprint_check_points(2.64, 1.2, 0.92, cover);
    EXPECT_EQ(points.front(), (Point2D{0.0, 0.0}));
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-0.4, 2.24);
    std::uniform_real_distribution<double> v(-0.6, 0.6);
    for (int i = 0; i < 2000; ++i) {
      const Point2D q{u(rng), v(rng)};
      double nearest = std::numeric_limits<double>::infinity();
      for (const Point2D& p : points) nearest = std::min(nearest, std::hypot(q.x - p.x, q.y - p.y));
      EXPECT_LE(nearest, cover + 1e-9);
    }
  }
  // The tricycle on its 0.8 m inflation at 0.05 m: one row along the centreline.
  const HybridAStarPlanner planner;
  const std::vector<Point2D> points = planner.check_points(0.05);
  for (const Point2D& p : points) EXPECT_EQ(p.y, 0.0);
  EXPECT_LE(points.size(), 7u);
  // No body: the origin alone, as the grid planners check.
  EXPECT_EQ(footprint_check_points(0.0, 0.0, 0.0, 0.3).size(), 1u);
  EXPECT_THROW(footprint_check_points(1.0, 1.0, 0.0, 0.0), std::invalid_argument);
}

TEST(HybridAStarPlanner, RejectsInvalidOptions) {
  const auto invalid = [](auto change) {
    HybridAStarOptions options;
    change(options);
    EXPECT_THROW(HybridAStarPlanner{options}, std::invalid_argument);
  };
  invalid([](HybridAStarOptions& o) { o.min_turning_radius_m = 0.0; });
  invalid([](HybridAStarOptions& o) { o.primitive_length_m = -1.0; });
  invalid([](HybridAStarOptions& o) { o.heading_bins = 2; });
  invalid([](HybridAStarOptions& o) { o.state_cell_m = 1.0; });  // not below the primitive
  invalid([](HybridAStarOptions& o) { o.cost_penalty_weight = -1.0; });
  invalid([](HybridAStarOptions& o) { o.max_expansions = 0; });
  invalid([](HybridAStarOptions& o) { o.path_step_m = std::nan(""); });
  invalid([](HybridAStarOptions& o) { o.steering_samples_per_side = 0; });
}

TEST(HybridAStarPlanner, HalfSteerPrimitivesAndOneInstanceForManyPlans) {
  HybridAStarOptions options;
  options.steering_samples_per_side = 2;
  HybridAStarPlanner planner(options);
  const PlanningGrid grid = tricycle_grid(serpentine());
  const PlanningGrid open = tricycle_grid(yard(20.0, 20.0));
  // Alternating grids of different sizes: the reused search state must not leak between plans.
  for (int round = 0; round < 2; ++round) {
    const Pose2D start{3.0, 4.0, 0.0};
    const Pose2D goal{4.0, 20.0, 0.0};
    expect_drivable(planner, grid, start, goal, planner.plan(grid, start, goal));
    const Pose2D open_start{10.0, 10.0, 1.0};
    const Pose2D open_goal{4.0, 15.0, 0.0};
    expect_drivable(planner, open, open_start, open_goal,
                    planner.plan(open, open_start, open_goal));
  }
}

}  // namespace
}  // namespace mobot::planning
