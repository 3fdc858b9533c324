#include "core/control/waypoint_follower.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "core/control/waypoint_follower.h"
#include "core/mapping/occupancy_grid.h"
#include "core/planning/astar_planner.h"
#include "core/planning/path_smoother.h"
#include "core/planning/planning_grid_builder.h"

namespace mobot::control {
namespace {

using geometry::Pose2D;
constexpr double kPi = std::numbers::pi;
constexpr double kDt = 0.02;  // the server's 50 Hz tick

// Distance from a point to the polyline.
double distance_to_path(const planning::Path& path, geometry::Point2D p) {
  const double s = path.project(p, 0.0, path.length_m() + 1.0);
  return planning::distance(path.point_at(s), p);
}

struct DriveResult {
  Pose2D pose;
  bool arrived = false;
  double time_s = 0.0;
  double max_cross_track_m = 0.0;
  double min_tracking_speed_mps = std::numeric_limits<double>::infinity();
};

// Closed loop at 50 Hz with an ideal unicycle; the measured velocity is the last command.
DriveResult drive(PathTracker& tracker, Pose2D pose, const planning::Path& path,
                  double max_time_s) {
  DriveResult run;
  msgs::Twist velocity;
  for (double t = 0.0; t < max_time_s; t += kDt) {
    const msgs::Twist u = tracker.compute(pose, velocity, t);
    if (tracker.arrived()) {
      run.arrived = true;
      run.time_s = t;
      EXPECT_EQ(u, msgs::Twist{});
      break;
    }
    if (tracker.status().state == TrackerState::kTracking && t > 2.0) {
      run.min_tracking_speed_mps = std::min(run.min_tracking_speed_mps, u.linear_mps);
    }
    pose.x += u.linear_mps * std::cos(pose.theta) * kDt;
    pose.y += u.linear_mps * std::sin(pose.theta) * kDt;
    pose.theta = geometry::wrap_angle(pose.theta + u.angular_radps * kDt);
    velocity = u;
    run.max_cross_track_m =
        std::max(run.max_cross_track_m, distance_to_path(path, {pose.x, pose.y}));
  }
  run.pose = pose;
  return run;
}

planning::Path l_shape() {
  return planning::Path(planning::PathSmoother::densify({{0.0, 0.0}, {3.0, 0.0}, {3.0, 3.0}}, 0.3));
}

TEST(WaypointFollower, FollowsAnLShapedPathWithoutStoppingAndArrives) {
  WaypointFollower follower;
  const planning::Path path = l_shape();
  ASSERT_TRUE(follower.set_path(path, kPi / 2.0));
  const DriveResult run = drive(follower, {0.0, 0.0, 0.0}, path, 40.0);
  ASSERT_TRUE(run.arrived);
  EXPECT_LT(std::hypot(run.pose.x - 3.0, run.pose.y - 3.0), 0.05);
  EXPECT_LT(std::abs(geometry::wrap_angle(run.pose.theta - kPi / 2.0)), 0.05);
  // Keeps moving through the intermediate waypoints (and the corner).
  EXPECT_GT(run.min_tracking_speed_mps, 0.25);
  // Stays near the path: the carrot law cuts the 90 degree corner by a bounded amount.
  EXPECT_LT(run.max_cross_track_m, 0.12);
  EXPECT_LT(run.time_s, 20.0);
  EXPECT_LT(follower.status().remaining_m, 0.05);
  std::printf("L path: arrived in %.2f s, max cross-track %.3f m, min cruise speed %.2f m/s\n",
              run.time_s, run.max_cross_track_m, run.min_tracking_speed_mps);
}

TEST(WaypointFollower, ArrivesWithARequestedHeadingAcrossThePath) {
  for (const double heading : {0.0, kPi, -kPi / 2.0}) {
    WaypointFollower follower;
    const planning::Path path = l_shape();
    ASSERT_TRUE(follower.set_path(path, heading));
    const DriveResult run = drive(follower, {0.0, 0.0, 0.0}, path, 60.0);
    ASSERT_TRUE(run.arrived) << heading;
    EXPECT_LT(std::hypot(run.pose.x - 3.0, run.pose.y - 3.0), 0.05) << heading;
    EXPECT_LT(std::abs(geometry::wrap_angle(run.pose.theta - heading)), 0.05) << heading;
  }
}

TEST(WaypointFollower, ArrivesUnderLocalisationAndSpeedNoise) {
  // Pose noise of a good EKF (+/-2 cm, +/-0.01 rad, uniform white) and C2's +/-5 % speed error.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int arrived = 0;
  for (int trial = 0; trial < 10; ++trial) {
    WaypointFollower follower;
    const planning::Path path = l_shape();
    ASSERT_TRUE(follower.set_path(path, kPi));
    Pose2D pose{0.0, 0.0, 0.0};
    msgs::Twist velocity;
    for (double t = 0.0; t < 60.0 && !follower.arrived(); t += kDt) {
      const Pose2D measured{pose.x + 0.02 * unit(rng), pose.y + 0.02 * unit(rng),
                            pose.theta + 0.01 * unit(rng)};
      msgs::Twist u = follower.compute(measured, velocity, t);
      u.linear_mps *= 1.0 + 0.05 * unit(rng);
      u.angular_radps *= 1.0 + 0.05 * unit(rng);
      pose.x += u.linear_mps * std::cos(pose.theta) * kDt;
      pose.y += u.linear_mps * std::sin(pose.theta) * kDt;
      pose.theta = geometry::wrap_angle(pose.theta + u.angular_radps * kDt);
      velocity = u;
    }
    if (!follower.arrived()) continue;
    ++arrived;
    // The true pose is within the tolerance plus the noise.
    EXPECT_LT(std::hypot(pose.x - 3.0, pose.y - 3.0), 0.05 + 0.03);
    EXPECT_LT(std::abs(geometry::wrap_angle(pose.theta - kPi)), 0.05 + 0.01);
  }
  EXPECT_EQ(arrived, 10);
}

TEST(WaypointFollower, TurnsOnTheSpotWhenThePathStartsBehind) {
  WaypointFollower follower;
  const planning::Path path(planning::PathSmoother::densify({{0.0, 0.0}, {-3.0, 0.0}}, 0.3));
  ASSERT_TRUE(follower.set_path(path, std::nullopt));  // end facing along the path: pi
  msgs::Twist first = follower.compute({0.0, 0.0, 0.0}, {}, 0.0);
  EXPECT_GE(first.linear_mps, 0.0);
  EXPECT_GT(std::abs(first.angular_radps), 1.0);
  follower.set_path(path, std::nullopt);
  const DriveResult run = drive(follower, {0.0, 0.0, 0.0}, path, 40.0);
  ASSERT_TRUE(run.arrived);
  EXPECT_LT(std::abs(geometry::wrap_angle(run.pose.theta - kPi)), 0.05);
  EXPECT_LT(run.max_cross_track_m, 0.2);
}

TEST(WaypointFollower, ReportsArrivalOnlyWhenStopped) {
  WaypointFollower follower;
  const planning::Path path(std::vector<geometry::Point2D>{{0.0, 0.0}, {1.0, 0.0}});
  ASSERT_TRUE(follower.set_path(path, 0.0));
  // In tolerance but still moving: not yet.
  follower.compute({0.99, 0.0, 0.0}, {0.3, 0.0}, 0.0);
  EXPECT_EQ(follower.status().state, TrackerState::kFinalApproach);
  EXPECT_FALSE(follower.arrived());
  EXPECT_EQ(follower.compute({0.99, 0.0, 0.0}, {0.01, 0.0}, 0.02), msgs::Twist{});
  EXPECT_TRUE(follower.arrived());
  // Latched: zero commands until a new path.
  EXPECT_EQ(follower.compute({0.5, 0.0, 0.0}, {}, 0.04), msgs::Twist{});
  EXPECT_TRUE(follower.arrived());
  ASSERT_TRUE(follower.set_path(path, 0.0));
  EXPECT_FALSE(follower.arrived());
}

TEST(WaypointFollower, RejectsBadPathsAndIdlesWithoutOne) {
  WaypointFollower follower;
  EXPECT_EQ(follower.compute({}, {}, 0.0), msgs::Twist{});
  EXPECT_EQ(follower.status().state, TrackerState::kIdle);
  EXPECT_FALSE(follower.set_path(planning::Path(), 0.0));
  EXPECT_FALSE(follower.set_path(planning::Path({{0.0, 0.0}, {std::nan(""), 1.0}}), 0.0));
  const planning::Path good(std::vector<geometry::Point2D>{{0.0, 0.0}, {2.0, 0.0}});
  EXPECT_FALSE(follower.set_path(good, std::nan("")));
  EXPECT_EQ(follower.status().state, TrackerState::kIdle);
  ASSERT_TRUE(follower.set_path(good, std::nullopt));
  EXPECT_EQ(follower.compute({std::nan(""), 0.0, 0.0}, {}, 0.0), msgs::Twist{});
  const msgs::Twist u = follower.compute({0.0, 0.0, 0.0}, {}, 0.0);
  EXPECT_GT(u.linear_mps, 0.5);
  EXPECT_LE(u.linear_mps, 1.3);
  follower.clear();
  EXPECT_EQ(follower.compute({0.0, 0.0, 0.0}, {}, 0.0), msgs::Twist{});
}

TEST(WaypointFollower, DrivesASmoothedAStarPathThroughADoorWithoutTouchingAWall) {
  // 8 x 6 m room split by a wall with a 1.2 m door; the goal is behind the wall.
  mapping::OccupancyGrid map(160, 120, 0.05, {}, mapping::OccupancyGrid::kFree);
  const auto wall = [&](int x0, int y0, int x1, int y1) {
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) map.set({x, y}, mapping::OccupancyGrid::kOccupied);
    }
  };
  wall(0, 0, 159, 1);
  wall(0, 118, 159, 119);
  wall(0, 0, 1, 119);
  wall(158, 0, 159, 119);
  wall(80, 0, 81, 70);
  wall(80, 95, 81, 119);
  const planning::PlanningGrid grid = planning::PlanningGridBuilder().build(map);
  planning::AStarPlanner planner;
  const Pose2D start{1.0, 1.0, kPi / 2.0};
  const Pose2D goal{7.0, 1.0, -kPi / 2.0};
  const planning::PlanResult plan = planner.plan(grid, start, goal);
  ASSERT_TRUE(plan.ok());
  const planning::Path path(planning::PathSmoother().smooth(grid, plan.points_in_map));

  WaypointFollower follower;
  ASSERT_TRUE(follower.set_path(path, goal.theta));
  Pose2D pose = start;
  msgs::Twist velocity;
  std::uint8_t worst_cost = 0;
  for (double t = 0.0; t < 60.0 && !follower.arrived(); t += kDt) {
    const msgs::Twist u = follower.compute(pose, velocity, t);
    pose.x += u.linear_mps * std::cos(pose.theta) * kDt;
    pose.y += u.linear_mps * std::sin(pose.theta) * kDt;
    pose.theta = geometry::wrap_angle(pose.theta + u.angular_radps * kDt);
    velocity = u;
    const auto cell = grid.cell_at({pose.x, pose.y});
    ASSERT_TRUE(cell.has_value());
    worst_cost = std::max(worst_cost, grid.cost(*cell));
  }
  EXPECT_TRUE(follower.arrived());
  EXPECT_LT(worst_cost, planning::PlanningGrid::kInscribed);  // never within 0.3 m of a wall
  EXPECT_LT(std::hypot(pose.x - goal.x, pose.y - goal.y), 0.05);
}

}  // namespace
}  // namespace mobot::control
