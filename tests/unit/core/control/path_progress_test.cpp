#include "core/control/path_progress.h"

#include <gtest/gtest.h>

#include <limits>

namespace mobot::control {
namespace {

planning::Path straight() { return planning::Path({{0.0, 0.0}, {2.0, 0.0}}); }

TEST(PathProgress, RefusesPathsItCannotFollowAndKeepsThePreviousOne) {
  PathProgress progress;
  ASSERT_TRUE(progress.start(straight(), 0.5));
  EXPECT_FALSE(progress.start(planning::Path(), std::nullopt));
  EXPECT_FALSE(progress.start(straight(), std::numeric_limits<double>::quiet_NaN()));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(progress.start(planning::Path({{0.0, 0.0}, {nan, 1.0}}), std::nullopt));
  EXPECT_DOUBLE_EQ(progress.goal().theta, 0.5);
  EXPECT_DOUBLE_EQ(progress.status().remaining_m, 2.0);
}

TEST(PathProgress, FollowsThenLatchesTheFinalApproach) {
  PathProgress progress;
  EXPECT_FALSE(progress.update({0.0, 0.0, 0.0}, 0.1, 1.0)) << "nothing to follow yet";
  ASSERT_TRUE(progress.start(straight(), std::nullopt));
  ASSERT_TRUE(progress.update({1.0, 0.05, 0.2}, 0.1, 1.0));
  EXPECT_TRUE(progress.tracking());
  EXPECT_NEAR(progress.status().progress_m, 1.0, 1e-9);
  EXPECT_NEAR(progress.status().remaining_m, 1.0, 1e-9);
  EXPECT_NEAR(progress.status().heading_error_rad, 0.2, 1e-12);
  ASSERT_TRUE(progress.update({1.95, 0.0, 0.0}, 0.1, 1.0));
  EXPECT_FALSE(progress.tracking());
  EXPECT_EQ(progress.status().state, TrackerState::kFinalApproach);
  // Latched: drifting out of the tolerance does not go back to tracking.
  ASSERT_TRUE(progress.update({1.7, 0.0, 0.0}, 0.1, 1.0));
  EXPECT_EQ(progress.status().state, TrackerState::kFinalApproach);
  EXPECT_FALSE(progress.update({std::numeric_limits<double>::infinity(), 0.0, 0.0}, 0.1, 1.0));
  progress.clear();
  EXPECT_EQ(progress.status().state, TrackerState::kIdle);
}

TEST(PathProgress, ArrivesWhenStoppedAndFacingTheGoal) {
  PathProgress progress;
  ASSERT_TRUE(progress.start(straight(), 0.0));
  ASSERT_TRUE(progress.update({2.0, 0.0, 0.01}, 0.1, 1.0));
  DynamicLimits limits;
  const msgs::Twist command = progress.final_approach(limits, {}, 0.05);
  EXPECT_EQ(command.linear_mps, 0.0);
  EXPECT_EQ(command.angular_radps, 0.0);
  EXPECT_EQ(progress.status().state, TrackerState::kArrived);
  EXPECT_FALSE(progress.update({2.0, 0.0, 0.01}, 0.1, 1.0));
}

}  // namespace
}  // namespace mobot::control
