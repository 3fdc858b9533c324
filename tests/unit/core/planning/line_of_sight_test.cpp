#include "core/planning/line_of_sight.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mobot::planning {
namespace {

TEST(LineOfSight, ReportsTheHighestCostTouched) {
  PlanningGrid grid(10, 10, 1.0, {});
  grid.set_cost({5, 2}, 100);
  grid.set_cost({5, 3}, 200);
  EXPECT_EQ(max_cost_along_segment(grid, {0.5, 2.5}, {9.5, 2.5}), 100);
  EXPECT_EQ(max_cost_along_segment(grid, {0.5, 3.5}, {9.5, 3.5}), 200);
  EXPECT_EQ(max_cost_along_segment(grid, {0.5, 4.5}, {9.5, 4.5}), 0);
  EXPECT_EQ(max_cost_along_segment(grid, {5.5, 0.5}, {5.5, 9.5}), 200);  // vertical
  EXPECT_EQ(max_cost_along_segment(grid, {5.5, 2.5}, {5.5, 2.5}), 100);  // a point
  EXPECT_TRUE(segment_is_clear(grid, {0.5, 2.5}, {9.5, 2.5}, 100));
  EXPECT_FALSE(segment_is_clear(grid, {0.5, 2.5}, {9.5, 2.5}, 99));
}

TEST(LineOfSight, CountsBothCellsBesideAnExactCornerCrossing) {
  PlanningGrid grid(4, 4, 1.0, {});
  grid.set_cost({1, 0}, PlanningGrid::kLethal);
  // The diagonal from (0.5, 0.5) to (1.5, 1.5) passes exactly through the corner (1, 1).
  EXPECT_FALSE(segment_is_clear(grid, {0.5, 0.5}, {1.5, 1.5}, 252));
  EXPECT_FALSE(segment_is_clear(grid, {1.5, 1.5}, {0.5, 0.5}, 252));
  grid.set_cost({1, 0}, PlanningGrid::kFree);
  EXPECT_TRUE(segment_is_clear(grid, {0.5, 0.5}, {3.5, 3.5}, 0));
}

TEST(LineOfSight, TouchesEveryCellAShallowLineCrosses) {
  PlanningGrid grid(20, 5, 0.1, {});
  // A line from (0.05, 0.05) to (1.95, 0.45) crosses rows 0..4; block a cell it clips near a row
  // change, which a plain Bresenham walk could step over.
  const geometry::Point2D a{0.05, 0.05};
  const geometry::Point2D b{1.95, 0.45};
  for (int x = 0; x < 20; ++x) {
    for (int y = 0; y < 5; ++y) {
      // Does the segment pass through cell (x, y)? Sample densely.
      bool touched = false;
      for (int k = 0; k <= 20000 && !touched; ++k) {
        const double t = k / 20000.0;
        const double px = a.x + t * (b.x - a.x);
        const double py = a.y + t * (b.y - a.y);
        touched = static_cast<int>(std::floor(px / 0.1)) == x &&
                  static_cast<int>(std::floor(py / 0.1)) == y;
      }
      PlanningGrid probe = grid;
      probe.set_cost({x, y}, PlanningGrid::kLethal);
      EXPECT_EQ(segment_is_clear(probe, a, b, 252), !touched) << x << "," << y;
    }
  }
}

TEST(LineOfSight, FailsOutsideTheGridAndOnNaN) {
  const PlanningGrid grid(10, 10, 1.0, {});
  EXPECT_FALSE(max_cost_along_segment(grid, {0.5, 0.5}, {10.5, 0.5}).has_value());
  EXPECT_FALSE(max_cost_along_segment(grid, {std::nan(""), 0.5}, {1.5, 0.5}).has_value());
  EXPECT_FALSE(segment_is_clear(grid, {0.5, 0.5}, {-0.5, 0.5}, 252));
  EXPECT_FALSE(max_cost_along_segment(PlanningGrid(), {0.0, 0.0}, {0.0, 0.0}).has_value());
}

}  // namespace
}  // namespace mobot::planning
