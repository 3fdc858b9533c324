#include "core/control/stop_and_rotate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/geometry/pose2d.h"

namespace mobot::control {
namespace {

constexpr double kDt = 0.02;

TEST(StopAndRotate, BrakesBeforeTurning) {
  const DynamicLimits limits;
  const StopAndRotate out = stop_and_rotate(limits, {0.2, 0.3}, 1.0, 0.05);
  EXPECT_NEAR(out.command.linear_mps, 0.17, 1e-12);
  EXPECT_NEAR(out.command.angular_radps, 0.26, 1e-12);
  EXPECT_FALSE(out.arrived);
}

TEST(StopAndRotate, TurnsToTheHeadingWithinTheLimitsAndArrivesStopped) {
  const DynamicLimits limits;
  for (const double start_error : {2.5, -1.0, 0.3, 0.07}) {
    double error = start_error;  // heading minus goal heading
    msgs::Twist velocity;
    bool arrived = false;
    double min_moving_rate = 10.0;
    for (int tick = 0; tick < 1000 && !arrived; ++tick) {
      const StopAndRotate out = stop_and_rotate(limits, velocity, error, 0.05);
      ASSERT_TRUE(reachable_window(limits, velocity).contains(out.command)) << start_error;
      EXPECT_EQ(out.command.linear_mps, 0.0);
      EXPECT_LE(std::abs(out.command.angular_radps), limits.max_angular_radps + 1e-12);
      arrived = out.arrived;
      if (arrived) {
        EXPECT_EQ(out.command, msgs::Twist{});
      }
      error = geometry::wrap_angle(error + out.command.angular_radps * kDt);
      velocity = out.command;
      if (std::abs(error) > 0.3 && std::abs(velocity.angular_radps) > 0.39) {
        min_moving_rate = std::min(min_moving_rate, std::abs(velocity.angular_radps));
      }
    }
    EXPECT_TRUE(arrived) << start_error;
    EXPECT_LE(std::abs(error), 0.05) << start_error;
    // Once up to speed, a turn on the spot runs at least the minimum rate.
    if (std::abs(start_error) > 0.5) {
      EXPECT_GE(min_moving_rate, 0.4 - 1e-9);
    }
  }
}

TEST(StopAndRotate, AlreadyThereAndStillIsArrived) {
  const StopAndRotate out = stop_and_rotate(DynamicLimits{}, {}, 0.01, 0.05);
  EXPECT_TRUE(out.arrived);
  EXPECT_EQ(out.command, msgs::Twist{});
  // Within tolerance but turning faster than one period of braking removes: not yet.
  EXPECT_FALSE(stop_and_rotate(DynamicLimits{}, {0.0, 0.3}, 0.01, 0.05).arrived);
}

}  // namespace
}  // namespace mobot::control
