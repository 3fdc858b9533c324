#include "core/estimation/wheel_odometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>

#include "core/kinematics/diff_drive.h"

namespace mobot::estimation {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(WheelOdometry, StraightRunAdvancesAlongHeading) {
  WheelOdometry odometry({0.1, 0.1, 0.6, 1000}, {1.0, 2.0, kPi / 2});
  odometry.update({0.0, 0, 0});
  // one wheel revolution on both wheels = 2 pi 0.1 m
  const auto& odom = odometry.update({1.0, 1000, 1000});
  EXPECT_NEAR(odom.pose.x, 1.0, 1e-9);
  EXPECT_NEAR(odom.pose.y, 2.0 + 2 * kPi * 0.1, 1e-9);
  EXPECT_NEAR(odom.twist.linear_mps, 2 * kPi * 0.1, 1e-9);
  EXPECT_NEAR(odom.twist.angular_radps, 0.0, 1e-12);
  EXPECT_NEAR(odometry.travelled_m(), 2 * kPi * 0.1, 1e-9);
}

TEST(WheelOdometry, OppositeWheelsTurnInPlace) {
  WheelOdometry odometry({0.1, 0.1, 0.6, 1000});
  odometry.update({0.0, 0, 0});
  // right forward, left back by 0.3 pi m each: dtheta = 0.6 pi / 0.6 = pi
  const int ticks = 1500;  // 1.5 rev * 0.2 pi m = 0.3 pi m
  const auto& odom = odometry.update({1.0, -ticks, ticks});
  EXPECT_NEAR(odom.pose.x, 0.0, 1e-9);
  EXPECT_NEAR(odom.pose.y, 0.0, 1e-9);
  EXPECT_NEAR(std::abs(odom.pose.theta), kPi, 1e-9);
}

// A Dashgo wheel turning slowly moves less than a tick per 20 ms period: the velocity over the
// window is still within one tick per window of the truth (a per-period one reads 0 or a tick).
TEST(WheelOdometry, ASlowTurnIsMeasuredOverTheWindowNotPerPeriod) {
  const OdometryParams params{0.064, 0.064, 0.3559, 1200, 0.1};
  WheelOdometry odometry(params);
  const double metres_per_tick = 2.0 * kPi * 0.064 / 1200;
  const double wheel_mps = 0.04 * 0.3559 / 2.0;  // 0.04 rad/s on the spot: 0.4 ticks a period
  const double tolerance_radps = 2.0 * metres_per_tick / 0.1 / 0.3559;
  int readings_off = 0;
  for (int k = 0; k <= 200; ++k) {
    const double t = 0.02 * k;
    const auto ticks = static_cast<std::int64_t>(std::floor(wheel_mps * t / metres_per_tick));
    const auto& odom = odometry.update({t, -ticks, ticks});
    if (k < 6) continue;
    EXPECT_NEAR(odom.twist.angular_radps, 0.04, tolerance_radps) << "at " << t << " s";
    EXPECT_NEAR(odom.twist.linear_mps, 0.0, 1e-12);
    readings_off += std::abs(odom.twist.angular_radps - 0.04) > 0.5 * 0.04 ? 1 : 0;
  }
  EXPECT_EQ(readings_off, 0);
}

TEST(WheelOdometry, AClockThatStepsBackRestartsTheVelocityWindow) {
  WheelOdometry odometry({0.1, 0.1, 0.6, 1000, 0.1});
  odometry.update({1.0, 0, 0});
  odometry.update({1.1, 100, 100});
  odometry.update({0.5, 100, 100});  // stepped back: pose kept, no velocity from it
  const auto& odom = odometry.update({0.6, 200, 200});
  EXPECT_NEAR(odom.twist.linear_mps, 100 * 2 * kPi * 0.1 / 1000 / 0.1, 1e-9);
  EXPECT_TRUE(std::isfinite(odom.twist.angular_radps));
}

TEST(DiffDrive, WheelsAndTwistAreInverse) {
  const msgs::Twist twist{0.4, -0.3};
  const auto wheels = kinematics::wheels_from_twist(twist, 0.6);
  const auto back = kinematics::twist_from_wheels(wheels, 0.6);
  EXPECT_NEAR(back.linear_mps, 0.4, 1e-12);
  EXPECT_NEAR(back.angular_radps, -0.3, 1e-12);
}

}  // namespace
}  // namespace mobot::estimation
