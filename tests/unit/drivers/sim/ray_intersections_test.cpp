#include "drivers/sim/ray_intersections.h"

#include <gtest/gtest.h>

namespace mobot::sim {
namespace {

constexpr double kTolerance = 1e-9;

TEST(RayIntersections, SphereEntryAndNormalWithAnUnnormalisedDirection) {
  const auto hit = intersect_sphere({0.0, 0.0, 1.0}, {2.0, 0.0, 0.0}, {5.0, 0.0, 1.0}, 0.5);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 2.25, kTolerance);  // x = 4.5 with the direction 2 m long
  EXPECT_NEAR(hit->normal.x, -1.0, kTolerance);
  EXPECT_FALSE(intersect_sphere({0.0, 0.0, 1.0}, {1.0, 0.0, 0.0}, {5.0, 0.6, 1.0}, 0.5));
  EXPECT_FALSE(intersect_sphere({0.0, 0.0, 1.0}, {-1.0, 0.0, 0.0}, {5.0, 0.0, 1.0}, 0.5));
  EXPECT_FALSE(intersect_sphere({5.0, 0.0, 1.0}, {1.0, 0.0, 0.0}, {5.0, 0.0, 1.0}, 0.5));
}

TEST(RayIntersections, CylinderSideCapAndMisses) {
  // Side.
  auto hit = intersect_upright_cylinder({0.0, 0.0, 0.5}, {1.0, 0.0, 0.0}, 3.0, 0.0, 0.5, 0.0, 1.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 2.5, kTolerance);
  EXPECT_NEAR(hit->normal.x, -1.0, kTolerance);
  // Over the top: a ray at 1.5 m misses a 1 m cylinder.
  EXPECT_FALSE(
      intersect_upright_cylinder({0.0, 0.0, 1.5}, {1.0, 0.0, 0.0}, 3.0, 0.0, 0.5, 0.0, 1.0));
  // Looking down onto the top cap.
  hit = intersect_upright_cylinder({3.0, 0.0, 2.0}, {0.1, 0.0, -1.0}, 3.0, 0.0, 0.5, 0.0, 1.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 1.0, kTolerance);
  EXPECT_NEAR(hit->normal.z, 1.0, kTolerance);
  // Looking up at a cylinder hanging from 1 to 2 m: the bottom cap.
  hit = intersect_upright_cylinder({3.0, 0.0, 0.5}, {0.0, 0.0, 1.0}, 3.0, 0.0, 0.5, 1.0, 2.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 0.5, kTolerance);
  EXPECT_NEAR(hit->normal.z, -1.0, kTolerance);
  // From inside.
  EXPECT_FALSE(
      intersect_upright_cylinder({3.0, 0.0, 0.5}, {1.0, 0.0, 0.0}, 3.0, 0.0, 0.5, 0.0, 1.0));
}

TEST(RayIntersections, BoxFaceEntered) {
  const Box3D box{2.0, -1.0, 3.0, 1.0, 0.7, 0.75, "table", false};
  auto hit = intersect_box({0.0, 0.0, 0.72}, {1.0, 0.0, 0.0}, box);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 2.0, kTolerance);
  EXPECT_NEAR(hit->normal.x, -1.0, kTolerance);
  // From above onto the top.
  hit = intersect_box({2.5, 0.0, 1.75}, {0.0, 0.0, -1.0}, box);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 1.0, kTolerance);
  EXPECT_NEAR(hit->normal.z, 1.0, kTolerance);
  // Under the table top.
  EXPECT_FALSE(intersect_box({0.0, 0.0, 0.5}, {1.0, 0.0, 0.0}, box));
  // Sideways into the y face.
  hit = intersect_box({2.5, -3.0, 0.72}, {0.0, 1.0, 0.0}, box);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 2.0, kTolerance);
  EXPECT_NEAR(hit->normal.y, -1.0, kTolerance);
}

}  // namespace
}  // namespace mobot::sim
