// What every registered path tracker must do alike (as every planner does in
// global_planner_contract_test): refuse bad paths and keep its state, command nothing without a
// path, follow a path to its end within the limits it was configured with, honour the goal
// heading, and stop for good on clear().
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "server/plugins/plugins.h"

namespace mobot::control {
namespace {

constexpr double kDt = 0.02;  // the server's 50 Hz tick

server::PluginContext contract_context() {
  server::PluginContext context;
  context.limits.max_linear_mps = 1.0;
  context.limits.max_angular_radps = 1.5;
  context.navigation.max_linear_mps = 0.6;
  return context;
}

const server::PluginSet<PathTracker>& trackers() {
  static const server::Plugins plugins = server::builtin_plugins();
  static const server::PluginSet<PathTracker> configured(plugins.trackers, YAML::Node(),
                                                         contract_context());
  return configured;
}

planning::Path l_shaped_path() {
  return planning::Path(std::vector<geometry::Point2D>{{0, 0}, {2, 0}, {2, 2}});
}

class PathTrackerContract : public ::testing::TestWithParam<std::string> {};

TEST_P(PathTrackerContract, RefusesBadPathsAndCommandsNothingWithoutOne) {
  const auto tracker = trackers().make(GetParam());
  ASSERT_NE(tracker, nullptr);
  EXPECT_EQ(tracker->name(), GetParam());
  EXPECT_EQ(tracker->status().state, TrackerState::kIdle);
  EXPECT_EQ(tracker->compute({0, 0, 0}, {}, 0.0), msgs::Twist{});
  EXPECT_FALSE(tracker->set_path(planning::Path(), std::nullopt));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(tracker->set_path(planning::Path(std::vector<geometry::Point2D>{{0, 0}, {nan, 1}}),
                                 std::nullopt));
  EXPECT_EQ(tracker->status().state, TrackerState::kIdle) << "a refused path changes nothing";
}

TEST_P(PathTrackerContract, FollowsAPathToItsEndWithinTheLimitsAndTheGoalHeading) {
  const auto tracker = trackers().make(GetParam());
  ASSERT_TRUE(tracker->set_path(l_shaped_path(), std::numbers::pi / 2));
  geometry::Pose2D pose{0, 0, 0};
  msgs::Twist velocity;
  double t = 0.0;
  for (; t < 60.0 && !tracker->arrived(); t += kDt) {
    const msgs::Twist u = tracker->compute(pose, velocity, t);
    ASSERT_TRUE(std::isfinite(u.linear_mps) && std::isfinite(u.angular_radps));
    EXPECT_LE(std::abs(u.linear_mps), contract_context().navigation.max_linear_mps + 1e-9);
    EXPECT_LE(std::abs(u.angular_radps), contract_context().limits.max_angular_radps + 1e-9);
    pose.x += u.linear_mps * std::cos(pose.theta) * kDt;
    pose.y += u.linear_mps * std::sin(pose.theta) * kDt;
    pose.theta = geometry::wrap_angle(pose.theta + u.angular_radps * kDt);
    velocity = u;
  }
  ASSERT_TRUE(tracker->arrived()) << GetParam() << " did not arrive in 60 s";
  EXPECT_LT(std::hypot(pose.x - 2.0, pose.y - 2.0),
            contract_context().navigation.goal_tolerance_m + 0.02);
  EXPECT_LT(std::abs(geometry::wrap_angle(pose.theta - std::numbers::pi / 2)),
            contract_context().navigation.goal_tolerance_rad + 0.02);
  EXPECT_EQ(tracker->compute(pose, velocity, t), msgs::Twist{}) << "arrived: commands are zero";
}

TEST_P(PathTrackerContract, ClearStopsForGood) {
  const auto tracker = trackers().make(GetParam());
  ASSERT_TRUE(tracker->set_path(l_shaped_path(), std::nullopt));
  EXPECT_NE(tracker->compute({0, 0, 0}, {}, 0.0), msgs::Twist{});
  tracker->clear();
  EXPECT_EQ(tracker->status().state, TrackerState::kIdle);
  EXPECT_EQ(tracker->compute({0, 0, 0}, {}, 0.02), msgs::Twist{});
}

INSTANTIATE_TEST_SUITE_P(EveryTracker, PathTrackerContract, ::testing::ValuesIn(trackers().names()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           return param.param;
                         });

}  // namespace
}  // namespace mobot::control
