#include "core/navigation/goal_navigator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "core/control/waypoint_follower.h"

namespace mobot::navigation {
namespace {

std::unique_ptr<control::PathTracker> lyapunov() {
  return std::make_unique<control::WaypointFollower>();
}

constexpr double kTick_s = 0.02;

Goal goal_to(double x, double y, std::optional<double> theta = std::nullopt) {
  Goal goal;
  goal.target = {x, y, theta.value_or(0.0)};
  goal.has_heading = theta.has_value();
  return goal;
}

planning::Path straight(double x0, double y0, double x1, double y1) {
  std::vector<geometry::Point2D> points;
  for (int i = 0; i <= 10; ++i) {
    const double f = i / 10.0;
    points.push_back({x0 + f * (x1 - x0), y0 + f * (y1 - y0)});
  }
  return planning::Path(points);
}

// Integrates a unicycle under the navigator's commands until the goal ends or time runs out.
geometry::Pose2D drive(GoalNavigator& navigator, geometry::Pose2D pose, double& now_s,
                       double duration_s, std::span<const msgs::RangeReading> sonar = {}) {
  msgs::Twist velocity;
  for (double end_s = now_s + duration_s; now_s < end_s; now_s += kTick_s) {
    const auto result = navigator.tick(now_s, pose, velocity, sonar);
    if (!result.command) break;
    velocity = *result.command;
    pose.x += velocity.linear_mps * std::cos(pose.theta) * kTick_s;
    pose.y += velocity.linear_mps * std::sin(pose.theta) * kTick_s;
    pose.theta = geometry::wrap_angle(pose.theta + velocity.angular_radps * kTick_s);
  }
  return pose;
}

TEST(GoalNavigator, DrivesToTheGoalAndSucceedsAtTheRequestedHeading) {
  GoalNavigator navigator({});
  double now_s = 0.0;
  Goal goal = goal_to(3.0, 0.0, 1.0);
  goal.id = 1;
  navigator.start(goal, straight(0, 0, 3, 0), lyapunov(), now_s);
  ASSERT_EQ(navigator.active_id(), 1);
  const geometry::Pose2D end = drive(navigator, {0, 0, 0}, now_s, 60.0);
  const auto done = navigator.find(1);
  ASSERT_TRUE(done);
  EXPECT_EQ(done->status, GoalStatus::kSucceeded);
  EXPECT_TRUE(done->reason.empty());
  ASSERT_TRUE(done->ended_s);
  EXPECT_NEAR(end.x, 3.0, 0.06);
  EXPECT_NEAR(end.y, 0.0, 0.06);
  EXPECT_NEAR(geometry::wrap_angle(end.theta - 1.0), 0.0, 0.06);
  EXPECT_FALSE(navigator.active_id());
  // Finished: no more commands.
  EXPECT_FALSE(navigator.tick(now_s, end, {}, {}).command);
}

TEST(GoalNavigator, ANewGoalPreemptsTheActiveOne) {
  GoalNavigator navigator({});
  Goal first = goal_to(3, 0);
  first.id = 1;
  Goal second = goal_to(0, 3);
  second.id = 2;
  navigator.start(first, straight(0, 0, 3, 0), lyapunov(), 0.0);
  navigator.take_changes();
  navigator.start(second, straight(0, 0, 0, 3), lyapunov(), 1.0);
  EXPECT_EQ(navigator.find(1)->status, GoalStatus::kCanceled);
  EXPECT_EQ(navigator.find(1)->reason, "preempted");
  EXPECT_EQ(navigator.active_id(), 2);
  const auto changes = navigator.take_changes();
  ASSERT_EQ(changes.size(), 2U);
  EXPECT_EQ(changes[0].id, 1);
  EXPECT_EQ(changes[0].status, GoalStatus::kCanceled);
  EXPECT_EQ(changes[1].id, 2);
  EXPECT_EQ(changes[1].status, GoalStatus::kActive);
  EXPECT_TRUE(navigator.take_changes().empty());
}

TEST(GoalNavigator, CancelEndsOnlyKnownGoalsAndLeavesFinishedOnesAlone) {
  GoalNavigator navigator({});
  Goal goal = goal_to(3, 0);
  goal.id = 7;
  navigator.start(goal, straight(0, 0, 3, 0), lyapunov(), 0.0);
  EXPECT_FALSE(navigator.cancel(8, 1.0));
  EXPECT_TRUE(navigator.cancel(7, 1.0));
  EXPECT_EQ(navigator.find(7)->status, GoalStatus::kCanceled);
  EXPECT_EQ(navigator.find(7)->reason, "canceled");
  navigator.end_active(GoalStatus::kFailed, "collision", 2.0);  // nothing active: no change
  EXPECT_EQ(navigator.find(7)->status, GoalStatus::kCanceled);
  EXPECT_TRUE(navigator.cancel(7, 3.0));
  EXPECT_DOUBLE_EQ(*navigator.find(7)->ended_s, 1.0);
}

TEST(GoalNavigator, AnUnknownControllerIsRefusedAndTheActiveGoalRunsOn) {
  GoalNavigator navigator({});
  navigator.start(goal_to(3, 0), straight(0, 0, 3, 0), lyapunov(), 0.0);
  Goal goal = goal_to(1, 0);
  goal.id = 99;
  goal.controller = "teleportation";
  // No registered tracker has that name: the caller has none to give.
  EXPECT_THROW(navigator.start(goal, straight(0, 0, 1, 0), nullptr, 0.5), std::invalid_argument);
  ASSERT_TRUE(navigator.active_id().has_value());
  EXPECT_NE(*navigator.active_id(), 99);
  EXPECT_FALSE(navigator.find(99).has_value());
}

TEST(GoalNavigator, KeepsABoundedHistory) {
  GoalNavigatorOptions options;
  options.history = 3;
  GoalNavigator navigator(options);
  for (int id = 1; id <= 5; ++id) {
    Goal goal = goal_to(1, 0);
    goal.id = id;
    navigator.start(goal, straight(0, 0, 1, 0), lyapunov(), id);
  }
  const auto goals = navigator.list();
  ASSERT_EQ(goals.size(), 3U);
  EXPECT_EQ(goals.front().id, 3);
  EXPECT_EQ(goals.back().id, 5);
  EXPECT_FALSE(navigator.find(1));
}

msgs::RangeReading echo_ahead(double range_m) {
  msgs::RangeReading reading;
  reading.sensor_in_base = {0.3, 0.0, 0.0};
  reading.cone_rad = 0.39;
  reading.range_min_m = 0.03;
  reading.range_max_m = 4.0;
  reading.range_m = range_m;
  return reading;
}

TEST(GoalNavigator, AnObstacleThatNeverClearsAsksForReplansThenFails) {
  GoalNavigatorOptions options;
  options.max_replans = 2;
  options.supervisor.blocked_timeout_s = 1.0;
  GoalNavigator navigator(options);
  Goal goal = goal_to(5, 0);
  goal.id = 1;
  navigator.start(goal, straight(0, 0, 5, 0), lyapunov(), 0.0);
  // An echo 0.2 m ahead of the sensor that follows the robot wherever it turns.
  const std::vector<msgs::RangeReading> sonar{echo_ahead(0.2)};
  int replans = 0;
  double now_s = 0.0;
  for (; now_s < 30.0 && navigator.active_id(); now_s += kTick_s) {
    const auto result = navigator.tick(now_s, {0, 0, 0}, {}, sonar);
    if (result.replan_needed) {
      ++replans;
      navigator.replan(1, straight(0, 0, 5, 0), now_s);
    }
  }
  EXPECT_EQ(replans, 2);
  EXPECT_EQ(navigator.find(1)->status, GoalStatus::kFailed);
  EXPECT_EQ(navigator.find(1)->reason, "blocked");
  EXPECT_EQ(navigator.find(1)->replans, 2);
}

TEST(GoalNavigator, AReplanForAGoalThatIsNoLongerActiveIsIgnored) {
  GoalNavigator navigator({});
  Goal goal = goal_to(3, 0);
  goal.id = 1;
  navigator.start(goal, straight(0, 0, 3, 0), lyapunov(), 0.0);
  navigator.cancel(1, 0.5);
  navigator.replan(1, straight(0, 0, 0, 3), 1.0);
  EXPECT_EQ(navigator.find(1)->status, GoalStatus::kCanceled);
  EXPECT_EQ(navigator.find(1)->replans, 0);
}

TEST(GoalNavigator, StatusNames) {
  EXPECT_EQ(to_string(GoalStatus::kPlanning), "planning");
  EXPECT_EQ(to_string(GoalStatus::kActive), "active");
  EXPECT_EQ(to_string(GoalStatus::kSucceeded), "succeeded");
  EXPECT_EQ(to_string(GoalStatus::kFailed), "failed");
  EXPECT_EQ(to_string(GoalStatus::kCanceled), "canceled");
}

}  // namespace
}  // namespace mobot::navigation

namespace mobot::navigation {
namespace {

TEST(GoalNavigatorStuck, ARobotThatDoesNotMoveFailsTheGoal) {
  GoalNavigatorOptions options;
  options.stuck_timeout_s = 3.0;
  GoalNavigator navigator(options);
  Goal goal = goal_to(5, 0);
  goal.id = 1;
  navigator.start(goal, straight(0, 0, 5, 0), lyapunov(), 0.0);
  double now_s = 0.0;
  // Wedged: the pose never changes whatever the navigator commands.
  for (; now_s < 10.0 && navigator.active_id(); now_s += kTick_s) {
    navigator.tick(now_s, {0, 0, 0}, {}, {});
  }
  EXPECT_EQ(navigator.find(1)->status, GoalStatus::kFailed);
  EXPECT_EQ(navigator.find(1)->reason, "stuck");
  EXPECT_NEAR(now_s, 3.0, 0.1);
}

}  // namespace
}  // namespace mobot::navigation
