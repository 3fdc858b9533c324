#include "core/costmap/grid_shift.h"

#include <gtest/gtest.h>

#include <numbers>

namespace mobot::costmap {
namespace {

using planning::PlanningGrid;

PlanningGrid numbered(int width, int height, geometry::Pose2D origin = {}) {
  PlanningGrid grid(width, height, 0.1, origin);
  for (std::size_t i = 0; i < grid.costs().size(); ++i) {
    grid.mutable_costs()[i] = static_cast<std::uint8_t>(i % 250);
  }
  return grid;
}

TEST(GridShift, KeepsTheSharedCellsAndFillsTheRest) {
  const PlanningGrid before = numbered(6, 5);
  for (const auto& [dx, dy] : {std::pair{2, 1}, {-1, 3}, {0, -2}, {-5, -4}, {3, 0}}) {
    PlanningGrid grid = before;
    shift_grid(grid, dx, dy, 255);
    EXPECT_NEAR(grid.origin().x, 0.1 * dx, 1e-12);
    EXPECT_NEAR(grid.origin().y, 0.1 * dy, 1e-12);
    for (int y = 0; y < 5; ++y) {
      for (int x = 0; x < 6; ++x) {
        const mapping::CellIndex old{x + dx, y + dy};
        const std::uint8_t expected = before.contains(old) ? before.cost(old) : 255;
        ASSERT_EQ(grid.cost({x, y}), expected) << dx << "," << dy << " at " << x << "," << y;
      }
    }
    // The cells that entered are exactly the filled ones.
    int entered = 0;
    for (const CellBounds& band : entered_cells(6, 5, dx, dy)) {
      entered += static_cast<int>(band.cell_count());
      for (int y = band.min_y; y <= band.max_y; ++y) {
        for (int x = band.min_x; x <= band.max_x; ++x) {
          EXPECT_FALSE(before.contains({x + dx, y + dy}));
        }
      }
    }
    const int kept = std::max(0, 6 - std::abs(dx)) * std::max(0, 5 - std::abs(dy));
    EXPECT_EQ(entered, 30 - kept) << dx << "," << dy;
  }
}

TEST(GridShift, ARotatedGridMovesAlongItsOwnAxes) {
  PlanningGrid grid = numbered(4, 4, {1.0, 1.0, std::numbers::pi / 2});
  const geometry::Point2D centre = grid.cell_center({2, 1});
  const std::uint8_t cost = grid.cost({2, 1});
  shift_grid(grid, 1, 0, 0);
  EXPECT_NEAR(grid.origin().x, 1.0, 1e-12);
  EXPECT_NEAR(grid.origin().y, 1.1, 1e-12);
  EXPECT_EQ(grid.cost({1, 1}), cost);
  EXPECT_NEAR(grid.cell_center({1, 1}).x, centre.x, 1e-12);
  EXPECT_NEAR(grid.cell_center({1, 1}).y, centre.y, 1e-12);
}

TEST(GridShift, NoShiftOrAnEmptyGridChangesNothing) {
  PlanningGrid grid = numbered(3, 3);
  const PlanningGrid before = grid;
  shift_grid(grid, 0, 0, 7);
  EXPECT_EQ(grid.costs(), before.costs());
  PlanningGrid empty;
  shift_grid(empty, 2, 2, 7);
  EXPECT_TRUE(empty.empty());
  EXPECT_TRUE(entered_cells(0, 5, 1, 1).empty());
  EXPECT_TRUE(entered_cells(5, 5, 0, 0).empty());
  EXPECT_TRUE(same_geometry(grid, before));
  EXPECT_FALSE(same_geometry(grid, numbered(3, 4)));
}

}  // namespace
}  // namespace mobot::costmap
