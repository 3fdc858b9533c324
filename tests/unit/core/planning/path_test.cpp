#include "core/planning/path.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace mobot::planning {
namespace {

TEST(Path, MeasuresArcLengthAndDropsDuplicates) {
  const Path path({{0.0, 0.0}, {0.0, 0.0}, {3.0, 0.0}, {3.0, 4.0}});
  EXPECT_EQ(path.size(), 3U);
  EXPECT_DOUBLE_EQ(path.length_m(), 7.0);
  EXPECT_DOUBLE_EQ(path.s_at_vertex(2), 7.0);
  EXPECT_EQ(path.point_at(1.5), (geometry::Point2D{1.5, 0.0}));
  EXPECT_EQ(path.point_at(5.0), (geometry::Point2D{3.0, 2.0}));
  EXPECT_EQ(path.point_at(-1.0), (geometry::Point2D{0.0, 0.0}));
  EXPECT_EQ(path.point_at(99.0), (geometry::Point2D{3.0, 4.0}));
  EXPECT_DOUBLE_EQ(path.heading_at(1.0), 0.0);
  EXPECT_DOUBLE_EQ(path.heading_at(3.5), std::numbers::pi / 2.0);
  EXPECT_DOUBLE_EQ(path.heading_at(3.0), std::numbers::pi / 2.0);  // at a vertex: the way out
  EXPECT_DOUBLE_EQ(path.heading_at(7.0), std::numbers::pi / 2.0);
}

TEST(Path, ProjectsWithinAWindowSoALoopDoesNotJump) {
  // Out along y = 0 and back along y = 0.2.
  const Path path({{0.0, 0.0}, {5.0, 0.0}, {5.0, 0.2}, {0.0, 0.2}});
  EXPECT_NEAR(path.project({1.0, 0.15}, 0.0, 2.0), 1.0, 1e-12);  // stays on the outbound leg
  EXPECT_NEAR(path.project({1.0, 0.15}, 8.0, 3.0), 9.2, 1e-12);  // inbound once past the turn
  EXPECT_NEAR(path.project({-1.0, 0.0}, 0.0, 2.0), 0.0, 1e-12);
  EXPECT_NEAR(path.project({4.0, 0.0}, 0.0, 2.0), 2.0, 1e-12);  // clamped to the window
}

TEST(Path, HandlesDegenerateAndNonFinitePaths) {
  const Path single({{1.0, 2.0}});
  EXPECT_DOUBLE_EQ(single.length_m(), 0.0);
  EXPECT_EQ(single.point_at(3.0), (geometry::Point2D{1.0, 2.0}));
  EXPECT_DOUBLE_EQ(single.project({5.0, 5.0}, 0.0, 1.0), 0.0);
  EXPECT_TRUE(Path().empty());
  EXPECT_FALSE(Path({{0.0, 0.0}, {std::nan(""), 1.0}}).all_finite());
  EXPECT_TRUE(single.all_finite());
}

}  // namespace
}  // namespace mobot::planning
