#include "core/costmap/ray_trace.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace mobot::costmap {
namespace {

using mapping::CellIndex;

std::vector<CellIndex> cells(CellIndex from, CellIndex to) {
  std::vector<CellIndex> out;
  trace_cells(from, to, [&out](CellIndex cell) { out.push_back(cell); });
  return out;
}

TEST(RayTrace, VisitsOneCellPerStepOfTheMajorAxisBothEndsIncluded) {
  EXPECT_EQ(cells({2, 2}, {2, 2}), (std::vector<CellIndex>{{2, 2}}));
  EXPECT_EQ(cells({0, 0}, {3, 0}), (std::vector<CellIndex>{{0, 0}, {1, 0}, {2, 0}, {3, 0}}));
  EXPECT_EQ(cells({0, 0}, {-2, -2}), (std::vector<CellIndex>{{0, 0}, {-1, -1}, {-2, -2}}));
  const auto steep = cells({0, 0}, {2, 7});
  ASSERT_EQ(steep.size(), 8U);
  EXPECT_EQ(steep.front(), (CellIndex{0, 0}));
  EXPECT_EQ(steep.back(), (CellIndex{2, 7}));
  for (std::size_t i = 1; i < steep.size(); ++i) {
    EXPECT_EQ(steep[i].y - steep[i - 1].y, 1);
    EXPECT_LE(std::abs(steep[i].x - steep[i - 1].x), 1);
  }
}

TEST(RayTrace, ClipsASegmentToTheGrid) {
  const planning::PlanningGrid grid(10, 10, 0.1, {});
  const auto inside = clip_to_grid(grid, {0.05, 0.05}, {0.55, 0.35});
  ASSERT_TRUE(inside.has_value());
  EXPECT_EQ(inside->from, (CellIndex{0, 0}));
  EXPECT_EQ(inside->to, (CellIndex{5, 3}));
  const auto through = clip_to_grid(grid, {-1.0, 0.55}, {2.0, 0.55});
  ASSERT_TRUE(through.has_value());
  EXPECT_EQ(through->from, (CellIndex{0, 5}));
  EXPECT_EQ(through->to, (CellIndex{9, 5}));
  EXPECT_FALSE(clip_to_grid(grid, {-1.0, -1.0}, {-0.5, 2.0}).has_value());
  EXPECT_FALSE(clip_to_grid(grid, {1.5, 0.5}, {1.5, 0.6}).has_value());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(clip_to_grid(grid, {nan, 0.5}, {0.5, 0.5}).has_value());
  EXPECT_FALSE(clip_to_grid(planning::PlanningGrid(), {0.0, 0.0}, {1.0, 1.0}).has_value());
}

}  // namespace
}  // namespace mobot::costmap
