#include "core/control/dwa_tracker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "core/costmap/inflation_layer.h"
#include "core/costmap/layered_costmap.h"
#include "core/costmap/static_layer.h"
#include "core/mapping/occupancy_grid.h"
#include "core/planning/path_smoother.h"

namespace mobot::control {
namespace {

using geometry::Pose2D;
using planning::PlanningGrid;
constexpr double kPi = std::numbers::pi;
constexpr double kDt = 0.02;  // the server's 50 Hz tick, DynamicLimits' control period

struct DriveResult {
  Pose2D pose;
  bool arrived = false;
  double time_s = 0.0;
  std::uint8_t worst_cost = 0;
  bool within_limits = true;
};

// Closed loop with an ideal unicycle (the measured velocity is the last command; with Trajectory
// Rollout, the last command ramped to at the limits as the velocity smoother does), the local
// costmap (when given) refreshed every tick around the robot. Commands stay in the window of one
// control period (of sim_time with Trajectory Rollout).
DriveResult drive(DwaTracker& tracker, Pose2D pose, double max_time_s,
                  costmap::LayeredCostmap* costmap = nullptr) {
  DriveResult run;
  msgs::Twist velocity;
  const DynamicLimits& limits = tracker.options().limits;
  for (double t = 0.0; t < max_time_s; t += kDt) {
    if (costmap != nullptr) {
      costmap->update(pose);
      tracker.set_local_costmap(costmap->snapshot());
      const auto cell = costmap->master().cell_at({pose.x, pose.y});
      if (cell) run.worst_cost = std::max(run.worst_cost, costmap->master().cost(*cell));
    }
    const msgs::Twist u = tracker.compute(pose, velocity, t);
    const bool rollout = tracker.options().accelerate_in_rollout;
    DynamicLimits window_limits = limits;
    if (rollout) window_limits.control_period_s = tracker.options().sim_time_s;
    const DynamicWindow window = reachable_window(window_limits, velocity);
    if (!window.contains(u) && !(tracker.blocked() && u == msgs::Twist{})) {
      run.within_limits = false;
      ADD_FAILURE() << "command (" << u.linear_mps << ", " << u.angular_radps
                    << ") outside the window at t = " << t;
    }
    if (tracker.arrived()) {
      run.arrived = true;
      run.time_s = t;
      EXPECT_EQ(u, msgs::Twist{});
      break;
    }
    msgs::Twist moved = u;
    if (rollout) {
      const auto ramp = [](double from, double to, double step) {
        return from + std::clamp(to - from, -step, step);
      };
      moved = {ramp(velocity.linear_mps, u.linear_mps, limits.linear_accel_mps2 * kDt),
               ramp(velocity.angular_radps, u.angular_radps, limits.angular_accel_radps2 * kDt)};
    }
    pose.x += moved.linear_mps * std::cos(pose.theta) * kDt;
    pose.y += moved.linear_mps * std::sin(pose.theta) * kDt;
    pose.theta = geometry::wrap_angle(pose.theta + moved.angular_radps * kDt);
    velocity = moved;
  }
  run.pose = pose;
  return run;
}

planning::Path straight() { return planning::Path({{0.0, 0.0}, {3.0, 0.0}}); }
planning::Path l_shape() {
  return planning::Path(planning::PathSmoother::densify({{0.0, 0.0}, {2.0, 0.0}, {2.0, 2.0}}, 0.3));
}

void expect_at(const DriveResult& run, double x, double y, double heading) {
  ASSERT_TRUE(run.arrived);
  EXPECT_LT(std::hypot(run.pose.x - x, run.pose.y - y), 0.05 + 1e-6);
  EXPECT_LT(std::abs(geometry::wrap_angle(run.pose.theta - heading)), 0.05 + 1e-6);
}

TEST(DwaTracker, FollowsAStraightPathToTheGoal) {
  DwaTracker tracker;
  ASSERT_TRUE(tracker.set_path(straight(), std::nullopt));
  const DriveResult run = drive(tracker, {0.0, 0.0, 0.0}, 40.0);
  expect_at(run, 3.0, 0.0, 0.0);
  EXPECT_TRUE(run.within_limits);
  EXPECT_LT(run.time_s, 3.0 / 0.3 + 8.0);
  std::printf("straight: arrived in %.2f s\n", run.time_s);
}

TEST(DwaTracker, FollowsAnLPathAndEndsWithTheGoalHeading) {
  for (const double heading : {kPi / 2, kPi, -kPi / 2}) {
    DwaTracker tracker;
    ASSERT_TRUE(tracker.set_path(l_shape(), heading));
    const DriveResult run = drive(tracker, {0.0, 0.0, 0.0}, 60.0);
    expect_at(run, 2.0, 2.0, heading);
    EXPECT_TRUE(run.within_limits);
    std::printf("L path to heading %.2f: arrived in %.2f s\n", heading, run.time_s);
  }
}

TEST(DwaTracker, CruisesAtItsMaximumSpeedOnAFreeStraight) {
  DwaTracker tracker;
  ASSERT_TRUE(tracker.set_path(planning::Path({{0.0, 0.0}, {10.0, 0.0}}), std::nullopt));
  Pose2D pose{0.0, 0.0, 0.0};
  msgs::Twist velocity;
  for (double t = 0.0; t < 3.0; t += kDt) {
    velocity = tracker.compute(pose, velocity, t);
    pose.x += velocity.linear_mps * kDt;
  }
  EXPECT_NEAR(velocity.linear_mps, 0.3, 1e-9);
  EXPECT_NEAR(velocity.angular_radps, 0.0, 1e-6);
  EXPECT_GT(tracker.trajectories_admissible(), 0);
  EXPECT_FALSE(tracker.chosen_trajectory().empty());
}

// A 6 x 4 m room at 0.05 m, free, with `walls` (cells) occupied; origin (-1, -2).
mapping::OccupancyGrid room(const std::vector<mapping::CellIndex>& walls) {
  mapping::OccupancyGrid map(120, 80, 0.05, {-1.0, -2.0, 0.0}, mapping::OccupancyGrid::kFree);
  for (const auto& cell : walls) map.set(cell, mapping::OccupancyGrid::kOccupied);
  return map;
}

costmap::LayeredCostmap local_costmap(const mapping::OccupancyGrid& map) {
  costmap::LayeredCostmapOptions options;
  options.rolling = true;
  options.lattice_origin_m = {map.origin().x, map.origin().y};
  costmap::LayeredCostmap costmap(options);
  costmap.add(std::make_unique<costmap::StaticLayer>()).set_map(map);
  costmap.add(std::make_unique<costmap::InflationLayer>());  // inscribed 0.2 m, radius 0.25 m
  return costmap;
}

// A 0.2 x 0.2 m box at x = 1.4..1.6 m whose near edge is `offset_m` left of the path.
std::vector<mapping::CellIndex> box_beside_path(double offset_m) {
  std::vector<mapping::CellIndex> box;
  for (double x = 1.4; x < 1.6; x += 0.05) {
    for (double y = offset_m; y < offset_m + 0.2; y += 0.05) {
      box.push_back({static_cast<int>(std::floor((x + 0.01 + 1.0) / 0.05)),
                     static_cast<int>(std::floor((y + 0.01 + 2.0) / 0.05))});
    }
  }
  return box;
}

TEST(DwaTracker, PassesAnObstacleBesideThePathWithoutTouchingIt) {
  // 0.22 m off: the path runs through the box's decaying band, outside its inscribed zone.
  costmap::LayeredCostmap costmap = local_costmap(room(box_beside_path(0.22)));
  DwaTracker tracker;
  ASSERT_TRUE(tracker.set_path(straight(), 0.0));
  const DriveResult run = drive(tracker, {0.0, 0.0, 0.0}, 60.0, &costmap);
  expect_at(run, 3.0, 0.0, 0.0);
  EXPECT_LT(run.worst_cost, PlanningGrid::kInscribed);
  EXPECT_TRUE(run.within_limits);
  std::printf("beside the box: arrived in %.2f s, worst cell cost %d\n", run.time_s,
              run.worst_cost);
}

TEST(DwaTracker, NeverEntersTheInscribedZoneOfAnObstacleOnThePath) {
  // 0.1 m off: the inscribed zone covers the path. DWA goes round or stops; it never touches.
  for (const double offset : {0.1, 0.0, -0.1}) {
    costmap::LayeredCostmap costmap = local_costmap(room(box_beside_path(offset)));
    DwaTracker tracker;
    ASSERT_TRUE(tracker.set_path(straight(), 0.0));
    const DriveResult run = drive(tracker, {0.0, 0.0, 0.0}, 20.0, &costmap);
    EXPECT_TRUE(run.arrived || tracker.blocked()) << offset;
    EXPECT_LT(run.worst_cost, PlanningGrid::kInscribed) << offset;
    EXPECT_TRUE(run.within_limits);
    std::printf("box %.2f m off the path: %s at (%.2f, %.2f), worst cell cost %d\n", offset,
                run.arrived ? "arrived" : "blocked", run.pose.x, run.pose.y, run.worst_cost);
  }
}

TEST(DwaTracker, StopsAndReportsBlockedWhenBoxedIn) {
  // A ring of walls 0.4 m around the robot: every move of more than a few centimetres enters the
  // inscribed zone.
  std::vector<mapping::CellIndex> ring;
  for (int i = 0; i < 360; ++i) {
    const double a = i * kPi / 180.0;
    ring.push_back({static_cast<int>(std::floor((0.4 * std::cos(a) + 1.0) / 0.05)),
                    static_cast<int>(std::floor((0.4 * std::sin(a) + 2.0) / 0.05))});
  }
  costmap::LayeredCostmap costmap = local_costmap(room(ring));
  DwaTracker tracker;
  ASSERT_TRUE(tracker.set_path(straight(), std::nullopt));
  Pose2D pose{0.0, 0.0, 0.0};
  msgs::Twist velocity;
  bool stopped = false;
  for (double t = 0.0; t < 10.0; t += kDt) {
    costmap.update(pose);
    tracker.set_local_costmap(costmap.snapshot());
    const msgs::Twist u = tracker.compute(pose, velocity, t);
    if (tracker.blocked()) {
      EXPECT_EQ(u, msgs::Twist{});
      stopped = true;
      break;
    }
    pose.x += u.linear_mps * std::cos(pose.theta) * kDt;
    pose.y += u.linear_mps * std::sin(pose.theta) * kDt;
    pose.theta = geometry::wrap_angle(pose.theta + u.angular_radps * kDt);
    velocity = u;
    EXPECT_LT(costmap.master().cost(*costmap.master().cell_at({pose.x, pose.y})),
              PlanningGrid::kInscribed);
  }
  EXPECT_TRUE(stopped);
  EXPECT_EQ(tracker.status().state, TrackerState::kTracking);
  EXPECT_FALSE(tracker.arrived());
  EXPECT_TRUE(tracker.chosen_trajectory().empty());
  EXPECT_LT(std::hypot(pose.x, pose.y), 0.2);
}

TEST(DwaTracker, StopsWhenAWallCrossesThePath) {
  // A corridor 1.6 m wide (walls at y = +-0.8 m) closed by a wall at x = 1.5 m.
  std::vector<mapping::CellIndex> wall;
  for (int y = 24; y <= 56; ++y) wall.push_back({50, y});
  for (int x = 0; x < 120; ++x) {
    wall.push_back({x, 24});
    wall.push_back({x, 56});
  }
  costmap::LayeredCostmap costmap = local_costmap(room(wall));
  DwaTracker tracker;
  ASSERT_TRUE(tracker.set_path(straight(), std::nullopt));
  const DriveResult run = drive(tracker, {0.0, 0.0, 0.0}, 30.0, &costmap);
  EXPECT_FALSE(run.arrived);
  EXPECT_TRUE(tracker.blocked());
  EXPECT_LT(run.worst_cost, PlanningGrid::kInscribed);
  EXPECT_LT(run.pose.x, 1.5 - 0.2);
  EXPECT_EQ(tracker.compute(run.pose, {}, 30.0), msgs::Twist{});
}

TEST(DwaTracker, TurnsOnTheSpotWhenThePathStartsBehind) {
  DwaTracker tracker;
  ASSERT_TRUE(tracker.set_path(planning::Path({{0.0, 0.0}, {-2.0, 0.0}}), std::nullopt));
  const DriveResult run = drive(tracker, {0.0, 0.0, 0.0}, 40.0);
  expect_at(run, -2.0, 0.0, kPi);
  EXPECT_TRUE(run.within_limits);
}

// The Dashgo's accelerations (0.3 m/s^2, 0.3 rad/s^2) and goal tolerances (0.10 m, 0.10 rad).
DwaOptions dashgo_options() {
  DwaOptions options;
  options.limits.linear_accel_mps2 = 0.3;
  options.limits.angular_accel_radps2 = 0.3;
  options.goal_tolerance_m = 0.10;
  options.goal_tolerance_rad = 0.10;
  return options;
}

// The Dashgo's case: its accelerations (0.3 m/s^2, 0.3 rad/s^2) leave a window of a few mm/s per
// tick, and a robot that stopped 0.11 m from the goal, off to its side, finds no arc that beats
// standing still. Within approach_radius_m it turns to the goal and drives at it.
TEST(DwaTracker, ReachesAGoalBesideItFromAStopJustOutsideTheTolerance) {
  for (const double approach_radius_m : {0.4, 0.0}) {
    DwaOptions options = dashgo_options();
    options.approach_radius_m = approach_radius_m;
    DwaTracker tracker(options);
    ASSERT_TRUE(tracker.set_path(straight(), std::nullopt));
    const DriveResult run = drive(tracker, {2.95, -0.10, -0.43}, 30.0);
    EXPECT_TRUE(run.within_limits);
    if (approach_radius_m > 0.0) {
      ASSERT_TRUE(run.arrived) << run.pose.x << ", " << run.pose.y;
      EXPECT_LT(std::hypot(run.pose.x - 3.0, run.pose.y), 0.10 + 1e-6);
      EXPECT_LT(std::abs(run.pose.theta), 0.10 + 1e-6);
    } else {
      EXPECT_FALSE(run.arrived) << "the case no longer needs the approach";
    }
  }
}

// The Dashgo's accelerations (0.3 m/s^2, 0.3 rad/s^2) on the L path, with the ramp to each sample
// simulated (Trajectory Rollout) and with DWA proper's one-period window.
TEST(DwaTracker, TrajectoryRolloutDrivesASlowlyAcceleratingBase) {
  for (const bool rollout : {false, true}) {
    DwaOptions options = dashgo_options();
    options.accelerate_in_rollout = rollout;
    DwaTracker tracker(options);
    ASSERT_TRUE(tracker.set_path(l_shape(), kPi / 2));
    const DriveResult run = drive(tracker, {0.0, 0.0, 0.0}, 60.0);
    EXPECT_TRUE(run.within_limits);
    std::printf("L path, accelerations 0.3, %s: %s in %.2f s\n", rollout ? "rollout" : "DWA",
                run.arrived ? "arrived" : "not arrived", run.arrived ? run.time_s : 60.0);
    if (rollout) {
      ASSERT_TRUE(run.arrived);
      EXPECT_LT(std::hypot(run.pose.x - 2.0, run.pose.y - 2.0), 0.10 + 1e-6);
      EXPECT_LT(run.time_s, 4.0 / 0.3 + 10.0);
    }
  }
}

TEST(DwaTracker, RefusesBadPathsAndANanPose) {
  DwaTracker tracker;
  EXPECT_EQ(tracker.compute({}, {}, 0.0), msgs::Twist{});
  EXPECT_EQ(tracker.status().state, TrackerState::kIdle);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(tracker.set_path(planning::Path(), 0.0));
  EXPECT_FALSE(tracker.set_path(planning::Path({{0.0, 0.0}, {nan, 1.0}}), 0.0));
  EXPECT_FALSE(tracker.set_path(straight(), nan));
  EXPECT_EQ(tracker.status().state, TrackerState::kIdle);
  ASSERT_TRUE(tracker.set_path(straight(), std::nullopt));
  EXPECT_EQ(tracker.compute({nan, 0.0, 0.0}, {}, 0.0), msgs::Twist{});
  EXPECT_EQ(tracker.compute({0.0, 0.0, nan}, {}, 0.0), msgs::Twist{});
  // A NaN velocity counts as standing still.
  const msgs::Twist u = tracker.compute({0.0, 0.0, 0.0}, {nan, nan}, 0.0);
  EXPECT_GT(u.linear_mps, 0.0);
  EXPECT_LE(u.linear_mps, 1.5 * kDt + 1e-9);
  tracker.clear();
  EXPECT_EQ(tracker.status().state, TrackerState::kIdle);
  EXPECT_EQ(tracker.compute({0.0, 0.0, 0.0}, {}, 0.0), msgs::Twist{});
}

TEST(DwaTracker, RejectsBadOptions) {
  DwaOptions options;
  options.sim_time_s = 0.0;
  EXPECT_THROW(DwaTracker{options}, std::invalid_argument);
  options = {};
  options.linear_samples = 0;
  EXPECT_THROW(DwaTracker{options}, std::invalid_argument);
  options = {};
  options.limits.max_linear_mps = std::nan("");
  EXPECT_THROW(DwaTracker{options}, std::invalid_argument);
  options = {};
  options.limits.min_in_place_angular_radps = 2.0;  // above the maximum
  EXPECT_THROW(DwaTracker{options}, std::invalid_argument);
  options = {};
  options.occdist_scale = -1.0;
  EXPECT_THROW(DwaTracker{options}, std::invalid_argument);
  options = {};
  options.approach_radius_m = -0.1;
  EXPECT_THROW(DwaTracker{options}, std::invalid_argument);
}

}  // namespace
}  // namespace mobot::control
