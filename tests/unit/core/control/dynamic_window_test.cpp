#include "core/control/dynamic_window.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace mobot::control {
namespace {

TEST(DynamicWindow, IsWhatOnePeriodOfAccelerationReachesWithinTheLimits) {
  const DynamicLimits limits;  // 0.3 m/s, 1.0 rad/s, 1.5 m/s^2, 2.0 rad/s^2, 0.02 s
  const DynamicWindow rest = reachable_window(limits, {});
  EXPECT_DOUBLE_EQ(rest.min_linear_mps, 0.0);  // forward only
  EXPECT_DOUBLE_EQ(rest.max_linear_mps, 0.03);
  EXPECT_DOUBLE_EQ(rest.min_angular_radps, -0.04);
  EXPECT_DOUBLE_EQ(rest.max_angular_radps, 0.04);
  const DynamicWindow cruising = reachable_window(limits, {0.29, 0.99});
  EXPECT_DOUBLE_EQ(cruising.min_linear_mps, 0.26);
  EXPECT_DOUBLE_EQ(cruising.max_linear_mps, 0.3);
  EXPECT_DOUBLE_EQ(cruising.max_angular_radps, 1.0);
  // Beyond the limits (a faster teleop before): the window sits at the limit.
  const DynamicWindow fast = reachable_window(limits, {1.0, -3.0});
  EXPECT_DOUBLE_EQ(fast.min_linear_mps, 0.3);
  EXPECT_DOUBLE_EQ(fast.max_linear_mps, 0.3);
  EXPECT_DOUBLE_EQ(fast.min_angular_radps, -1.0);
  EXPECT_DOUBLE_EQ(fast.max_angular_radps, -1.0);
  // Not finite: as if at rest.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_DOUBLE_EQ(reachable_window(limits, {nan, nan}).max_linear_mps, 0.03);
}

TEST(DynamicWindow, ClampsAndContains) {
  const DynamicWindow window{0.1, 0.2, -0.5, 0.5};
  EXPECT_EQ(window.clamp({1.0, -1.0}), (msgs::Twist{0.2, -0.5}));
  EXPECT_EQ(window.clamp({0.15, 0.1}), (msgs::Twist{0.15, 0.1}));
  EXPECT_TRUE(window.contains({0.2, 0.5}));
  EXPECT_FALSE(window.contains({0.0, 0.0}));
  EXPECT_FALSE(window.contains({0.15, 0.6}));
}

TEST(DynamicWindow, ValidatesLimits) {
  EXPECT_TRUE(valid(DynamicLimits{}));
  DynamicLimits limits;
  limits.control_period_s = 0.0;
  EXPECT_FALSE(valid(limits));
  limits = {};
  limits.linear_accel_mps2 = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(valid(limits));
  limits = {};
  limits.min_in_place_angular_radps = -0.1;
  EXPECT_FALSE(valid(limits));
  limits.min_in_place_angular_radps = 1.5;
  EXPECT_FALSE(valid(limits));
}

}  // namespace
}  // namespace mobot::control
