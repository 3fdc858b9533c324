#include "core/estimation/wheel_odometry.h"

#include <gtest/gtest.h>

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

TEST(DiffDrive, WheelsAndTwistAreInverse) {
  const msgs::Twist twist{0.4, -0.3};
  const auto wheels = kinematics::wheels_from_twist(twist, 0.6);
  const auto back = kinematics::twist_from_wheels(wheels, 0.6);
  EXPECT_NEAR(back.linear_mps, 0.4, 1e-12);
  EXPECT_NEAR(back.angular_radps, -0.3, 1e-12);
}

}  // namespace
}  // namespace mobot::estimation
