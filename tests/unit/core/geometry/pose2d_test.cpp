#include "core/geometry/pose2d.h"

#include <gtest/gtest.h>

#include <numbers>

namespace mobot::geometry {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(WrapAngle, KeepsAnglesInsideHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(wrap_angle(0.0), 0.0);
  EXPECT_DOUBLE_EQ(wrap_angle(kPi), kPi);
  EXPECT_DOUBLE_EQ(wrap_angle(-kPi), kPi);
  EXPECT_NEAR(wrap_angle(3 * kPi), kPi, 1e-12);
  EXPECT_NEAR(wrap_angle(2 * kPi + 0.1), 0.1, 1e-12);
  EXPECT_NEAR(wrap_angle(-2 * kPi - 0.1), -0.1, 1e-12);
}

TEST(Compose, InverseUndoesPose) {
  const Pose2D a{1.0, -2.0, 0.7};
  const Pose2D identity = compose(a, inverse(a));
  EXPECT_NEAR(identity.x, 0.0, 1e-12);
  EXPECT_NEAR(identity.y, 0.0, 1e-12);
  EXPECT_NEAR(identity.theta, 0.0, 1e-12);
}

TEST(Compose, RotatesChildIntoParent) {
  const Pose2D a{1.0, 0.0, kPi / 2};
  const Pose2D b{1.0, 0.0, 0.0};
  const Pose2D c = compose(a, b);
  EXPECT_NEAR(c.x, 1.0, 1e-12);
  EXPECT_NEAR(c.y, 1.0, 1e-12);
  EXPECT_NEAR(c.theta, kPi / 2, 1e-12);
}

TEST(IsFinite, RejectsNanAndInf) {
  EXPECT_TRUE(is_finite({1, 2, 3}));
  EXPECT_FALSE(is_finite({std::nan(""), 0, 0}));
  EXPECT_FALSE(is_finite({0, 0, 1.0 / 0.0}));
}

}  // namespace
}  // namespace mobot::geometry
