#include "drivers/sim/oriented_rect.h"

#include <gtest/gtest.h>

#include <numbers>

namespace mobot::sim {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(OrientedRect, OverlapsAxisAlignedBoxes) {
  const OrientedRect body{{0.0, 0.0, 0.0}, 0.3, 0.3};
  EXPECT_TRUE(overlaps(body, {0.2, -0.1, 1.0, 0.1}));
  EXPECT_FALSE(overlaps(body, {0.31, -0.1, 1.0, 0.1}));
  // Touching is not overlapping: a robot may stand flush against a wall.
  EXPECT_FALSE(overlaps(body, {0.3, -0.1, 1.0, 0.1}));
  // Turned by 45 degrees the corner reaches 0.3 * sqrt(2) = 0.424.
  const OrientedRect turned{{0.0, 0.0, kPi / 4}, 0.3, 0.3};
  EXPECT_TRUE(overlaps(turned, {0.40, -0.01, 1.0, 0.01}));
  EXPECT_FALSE(overlaps(turned, {0.43, -0.01, 1.0, 0.01}));
  // Near the corner but outside the rotated square: only the rotated axes separate them.
  EXPECT_FALSE(overlaps(turned, {0.25, 0.25, 0.4, 0.4}));
  EXPECT_TRUE(overlaps(body, {0.25, 0.25, 0.4, 0.4}));
}

TEST(OrientedRect, OverlapsCircles) {
  const OrientedRect body{{1.0, 1.0, kPi / 2}, 0.5, 0.2};  // long axis along map y
  EXPECT_TRUE(overlaps_circle(body, {1.0, 1.6}, 0.2));
  EXPECT_FALSE(overlaps_circle(body, {1.0, 1.75}, 0.2));
  EXPECT_FALSE(overlaps_circle(body, {1.45, 1.0}, 0.2));
  EXPECT_TRUE(overlaps_circle(body, {1.35, 1.0}, 0.2));
  EXPECT_TRUE(overlaps_circle(body, {1.0, 1.0}, 0.01));  // inside
}

TEST(OrientedRect, BoundingBoxOfATurnedRect) {
  const AxisAlignedRect box = bounding_box({{1.0, 2.0, kPi / 2}, 0.5, 0.2});
  EXPECT_NEAR(box.min_x_m, 0.8, 1e-12);
  EXPECT_NEAR(box.max_x_m, 1.2, 1e-12);
  EXPECT_NEAR(box.min_y_m, 1.5, 1e-12);
  EXPECT_NEAR(box.max_y_m, 2.5, 1e-12);
}

}  // namespace
}  // namespace mobot::sim
