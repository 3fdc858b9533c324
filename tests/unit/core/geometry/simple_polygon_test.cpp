#include "core/geometry/simple_polygon.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace mobot::geometry {
namespace {

using Ring = std::vector<Point2D>;

std::string error_of(const Ring& ring) { return SimplePolygon::error(ring).value_or(""); }

TEST(SimplePolygon, AcceptsConvexAndConcavePolygonsInEitherOrientation) {
  const Ring square{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  EXPECT_FALSE(SimplePolygon::error(square).has_value());
  EXPECT_DOUBLE_EQ(SimplePolygon(square).signed_area_m2(), 1.0);
  const Ring clockwise{{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  EXPECT_DOUBLE_EQ(SimplePolygon(clockwise).signed_area_m2(), -1.0);
  // An L (concave at (1, 1)).
  const Ring ell{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  const SimplePolygon l_shape(ell);
  EXPECT_DOUBLE_EQ(l_shape.signed_area_m2(), 3.0);
  EXPECT_TRUE(l_shape.contains({0.5, 1.5}));
  EXPECT_TRUE(l_shape.contains({1.5, 0.5}));
  EXPECT_FALSE(l_shape.contains({1.5, 1.5}));  // the notch
  EXPECT_FALSE(l_shape.contains({-0.1, 0.5}));
  EXPECT_EQ(l_shape.min_corner(), (Point2D{0, 0}));
  EXPECT_EQ(l_shape.max_corner(), (Point2D{2, 2}));
}

TEST(SimplePolygon, DropsARepeatedClosingVertex) {
  const SimplePolygon triangle(Ring{{0, 0}, {1, 0}, {0, 1}, {0, 0}});
  EXPECT_EQ(triangle.vertices().size(), 3U);
  EXPECT_DOUBLE_EQ(triangle.signed_area_m2(), 0.5);
}

TEST(SimplePolygon, RefusesTooFewOrTooManyVertices) {
  EXPECT_EQ(error_of({}), "a polygon needs 3 to 256 vertices, got 0");
  EXPECT_EQ(error_of({{0, 0}, {1, 0}}), "a polygon needs 3 to 256 vertices, got 2");
  // Closed by repeating the first vertex, a triangle of two distinct points is still two.
  EXPECT_EQ(error_of({{0, 0}, {1, 0}, {0, 0}}), "a polygon needs 3 to 256 vertices, got 2");
  Ring circle;
  for (int i = 0; i < 257; ++i) {
    circle.push_back(
        {std::cos(i * 2.0 * std::numbers::pi / 257), std::sin(i * 2.0 * std::numbers::pi / 257)});
  }
  EXPECT_EQ(error_of(circle), "a polygon needs 3 to 256 vertices, got 257");
  circle.pop_back();
  EXPECT_FALSE(SimplePolygon::error(circle).has_value());
}

TEST(SimplePolygon, RefusesNonFiniteVertices) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(error_of({{0, 0}, {1, nan}, {0, 1}}), "vertex 1 is not finite");
  EXPECT_EQ(error_of({{0, 0}, {1, 0}, {inf, 1}}), "vertex 2 is not finite");
}

TEST(SimplePolygon, RefusesDegeneratePolygons) {
  EXPECT_EQ(error_of({{0, 0}, {1, 0}, {1, 0}, {0, 1}}), "vertex 2 repeats vertex 1");
  EXPECT_EQ(error_of({{0, 0}, {1, 1}, {2, 2}}),
            "the polygon has no area (its vertices are collinear)");
  EXPECT_EQ(error_of({{0, 0}, {1, 0}, {2, 0}, {3, 0}}),
            "the polygon has no area (its vertices are collinear)");
}

TEST(SimplePolygon, RefusesSelfIntersections) {
  // A bow tie: edges 0-1 and 2-3 cross.
  EXPECT_EQ(error_of({{0, 0}, {1, 1}, {1, 0}, {0, 1}}),
            "edge 0-1 meets edge 2-3 (the polygon intersects itself)");
  // Two squares touching at one vertex (a figure eight through (1, 1)).
  EXPECT_EQ(error_of({{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {1, 2}, {1, 1}, {0, 1}}),
            "edge 1-2 meets edge 5-6 (the polygon intersects itself)");
  // A vertex lying on a non-adjacent edge.
  EXPECT_EQ(error_of({{0, 0}, {2, 0}, {2, 2}, {1, 0}, {0, 2}}),
            "edge 0-1 meets edge 2-3 (the polygon intersects itself)");
  // A zero-width spike: edge 1-2 runs back along edge 0-1.
  EXPECT_EQ(error_of({{0, 0}, {2, 0}, {1, 0}, {1, 1}}),
            "edge 1-2 doubles back along edge 0-1 (the polygon intersects itself)");
}

TEST(SimplePolygon, ConstructorThrowsTheErrorMessage) {
  try {
    SimplePolygon(Ring{{0, 0}, {1, 1}, {1, 0}, {0, 1}});
    FAIL() << "a bow tie was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_EQ(std::string(error.what()), "edge 0-1 meets edge 2-3 (the polygon intersects itself)");
  }
}

}  // namespace
}  // namespace mobot::geometry
