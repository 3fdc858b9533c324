#include "core/control/velocity_smoother.h"

#include <gtest/gtest.h>

namespace mobot::control {
namespace {

TEST(VelocitySmoother, RampsWithinAccelerationLimits) {
  VelocitySmoother smoother({1.0, 2.0, 0.5, 1.0});
  EXPECT_DOUBLE_EQ(smoother.step({1.0, 2.0}, 0.1).linear_mps, 0.05);
  EXPECT_DOUBLE_EQ(smoother.current().angular_radps, 0.1);
  for (int i = 0; i < 100; ++i) smoother.step({1.0, 2.0}, 0.1);
  EXPECT_DOUBLE_EQ(smoother.current().linear_mps, 1.0);
  EXPECT_DOUBLE_EQ(smoother.current().angular_radps, 2.0);
}

TEST(VelocitySmoother, ClampsTargetsAboveTheSpeedLimits) {
  VelocitySmoother smoother({0.5, 0.7, 100.0, 100.0});
  const auto& out = smoother.step({3.0, -3.0}, 0.1);
  EXPECT_DOUBLE_EQ(out.linear_mps, 0.5);
  EXPECT_DOUBLE_EQ(out.angular_radps, -0.7);
}

TEST(VelocitySmoother, HaltStopsAtOnce) {
  VelocitySmoother smoother({1.0, 1.0, 100.0, 100.0});
  smoother.step({1.0, 1.0}, 0.1);
  smoother.halt();
  EXPECT_EQ(smoother.current(), msgs::Twist{});
}

}  // namespace
}  // namespace mobot::control
