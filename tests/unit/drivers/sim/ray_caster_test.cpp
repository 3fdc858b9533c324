#include "drivers/sim/ray_caster.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "tests/unit/drivers/sim/sim_test_support.h"

namespace mobot::sim {
namespace {

using mapping::OccupancyGrid;
using testing::fill_cells;

constexpr double kPi = std::numbers::pi;

// 10 x 10 m at 0.1 m with a wall filling column 50 (x 5.0..5.1 m).
OccupancyGrid grid_with_vertical_wall() {
  OccupancyGrid grid(100, 100, 0.1, {}, OccupancyGrid::kFree);
  fill_cells(grid, 50, 0, 50, 99);
  return grid;
}

TEST(RayCaster, HitsAWallAtTheComputedDistance) {
  const RayCaster caster(grid_with_vertical_wall());
  const auto straight = caster.cast({1.0, 2.05}, 0.0, 80.0);
  ASSERT_TRUE(straight.has_value());
  EXPECT_NEAR(*straight, 4.0, 1e-9);
  const auto diagonal = caster.cast({1.0, 2.05}, kPi / 4, 80.0);
  ASSERT_TRUE(diagonal.has_value());
  EXPECT_NEAR(*diagonal, 4.0 * std::numbers::sqrt2, 1e-9);
  // From the far side the ray enters the wall at its right face, x = 5.1.
  const auto back = caster.cast({9.0, 7.0}, kPi, 80.0);
  ASSERT_TRUE(back.has_value());
  EXPECT_NEAR(*back, 3.9, 1e-9);
}

TEST(RayCaster, NoReturnInOpenSpaceOrBeyondRange) {
  const RayCaster caster(grid_with_vertical_wall());
  EXPECT_FALSE(caster.cast({1.0, 2.05}, kPi, 80.0).has_value());      // leaves the grid
  EXPECT_FALSE(caster.cast({1.0, 2.05}, kPi / 2, 80.0).has_value());  // along the free strip
  EXPECT_FALSE(caster.cast({1.0, 2.05}, 0.0, 3.99).has_value());      // wall beyond range
  EXPECT_TRUE(caster.cast({1.0, 2.05}, 0.0, 4.01).has_value());
  // Outside the grid, pointing away from it.
  EXPECT_FALSE(caster.cast({-3.0, 2.0}, kPi, 80.0).has_value());
  EXPECT_FALSE(caster.cast({-3.0, 2.0}, kPi / 2, 80.0).has_value());
}

TEST(RayCaster, RayFromOutsideEntersTheGrid) {
  const RayCaster caster(grid_with_vertical_wall());
  const auto hit = caster.cast({-2.0, 2.05}, 0.0, 80.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(*hit, 7.0, 1e-9);
  EXPECT_FALSE(caster.cast({-2.0, 2.05}, 0.0, 6.9).has_value());
}

TEST(RayCaster, StartingInsideAWallHitsAtZero) {
  const RayCaster caster(grid_with_vertical_wall());
  const auto hit = caster.cast({5.05, 3.0}, 1.0, 80.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(*hit, 0.0);
}

TEST(RayCaster, BeamParallelToAWallPassesIt) {
  // A wall along row 20 (y 2.0..2.1) from x 0 to 3 m, and a cross wall at column 80 (x 8.0).
  OccupancyGrid grid(100, 100, 0.1, {}, OccupancyGrid::kFree);
  fill_cells(grid, 0, 20, 29, 20);
  fill_cells(grid, 80, 0, 80, 99);
  const RayCaster caster(grid);
  for (const double y_m : {1.95, 2.15, 1.999}) {
    const auto hit = caster.cast({0.5, y_m}, 0.0, 80.0);
    ASSERT_TRUE(hit.has_value()) << y_m;
    EXPECT_NEAR(*hit, 7.5, 1e-9) << y_m;
  }
}

TEST(RayCaster, UnknownCellsAreTransparent) {
  OccupancyGrid grid(50, 10, 0.1, {}, OccupancyGrid::kUnknown);
  fill_cells(grid, 40, 0, 40, 9);
  fill_cells(grid, 20, 0, 20, 9, 40);  // below the occupied threshold
  const RayCaster caster(grid);
  const auto hit = caster.cast({0.05, 0.55}, 0.0, 80.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(*hit, 3.95, 1e-9);
}

TEST(RayCaster, EmptyGridHasNoReturns) {
  const RayCaster caster(OccupancyGrid(30, 30, 0.05, {}, OccupancyGrid::kFree));
  for (double angle = -kPi; angle < kPi; angle += 0.1) {
    EXPECT_FALSE(caster.cast({0.7, 0.8}, angle, 80.0).has_value()) << angle;
  }
}

TEST(RayCaster, HonoursARotatedAndOffsetOrigin) {
  // The grid's x axis points along the map's y axis; its column 30 is the map line y = 1 + 3.0.
  OccupancyGrid grid(100, 50, 0.1, {2.0, 1.0, kPi / 2}, OccupancyGrid::kFree);
  fill_cells(grid, 30, 0, 30, 49);
  const RayCaster caster(grid);
  const auto hit = caster.cast({1.0, 2.0}, kPi / 2, 80.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(*hit, 2.0, 1e-9);
}

TEST(CastToCircle, MatchesTheGeometry) {
  const auto head_on = cast_to_circle({0.0, 0.0}, 0.0, {5.0, 0.0}, 1.0);
  ASSERT_TRUE(head_on.has_value());
  EXPECT_NEAR(*head_on, 4.0, 1e-12);
  const auto offset = cast_to_circle({0.0, 0.0}, 0.0, {5.0, 0.6}, 1.0);
  ASSERT_TRUE(offset.has_value());
  EXPECT_NEAR(*offset, 4.2, 1e-12);
  EXPECT_FALSE(cast_to_circle({0.0, 0.0}, 0.0, {5.0, 1.01}, 1.0).has_value());
  EXPECT_FALSE(cast_to_circle({0.0, 0.0}, kPi, {5.0, 0.0}, 1.0).has_value());
  EXPECT_EQ(cast_to_circle({5.2, 0.1}, 2.0, {5.0, 0.0}, 1.0), 0.0);
}

// Random walls of random sizes on a grid of `width` x `height`.
OccupancyGrid random_grid(std::mt19937_64& rng, int width, int height, int walls) {
  OccupancyGrid grid(width, height, 0.05, {-1.0, 2.0, 0.0}, OccupancyGrid::kFree);
  std::uniform_int_distribution<int> x_of(0, width - 1);
  std::uniform_int_distribution<int> y_of(0, height - 1);
  std::uniform_int_distribution<int> length(0, 40);
  std::bernoulli_distribution vertical(0.5);
  for (int i = 0; i < walls; ++i) {
    const int x = x_of(rng);
    const int y = y_of(rng);
    const int n = length(rng);
    if (vertical(rng)) {
      fill_cells(grid, x, y, x, std::min(y + n, height - 1));
    } else {
      fill_cells(grid, x, y, std::min(x + n, width - 1), y);
    }
  }
  return grid;
}

TEST(RayCaster, SphereTracingEqualsCellByCellOnRandomGrids) {
  std::mt19937_64 rng(7);
  for (const int walls : {0, 5, 60, 600}) {
    const OccupancyGrid grid = random_grid(rng, 300, 200, walls);
    const RayCaster caster(grid);
    // Origins also outside the grid (it spans x -1..14, y 2..12).
    std::uniform_real_distribution<double> x_of(-3.0, 16.0);
    std::uniform_real_distribution<double> y_of(0.0, 14.0);
    std::uniform_real_distribution<double> angle_of(-kPi, kPi);
    std::uniform_real_distribution<double> range_of(0.5, 30.0);
    int hits = 0;
    for (int i = 0; i < 5000; ++i) {
      const geometry::Point2D from{x_of(rng), y_of(rng)};
      const double angle = angle_of(rng);
      const double range = range_of(rng);
      const auto fast = caster.cast(from, angle, range);
      const auto reference = caster.cast_cell_by_cell(from, angle, range);
      ASSERT_EQ(fast.has_value(), reference.has_value())
          << "walls " << walls << " from " << from.x << ", " << from.y << " angle " << angle;
      if (fast) {
        ++hits;
        ASSERT_NEAR(*fast, *reference, 1e-9);
        ASSERT_LE(*fast, range);
      }
    }
    if (walls >= 60) {
      EXPECT_GT(hits, 1000) << walls;
    }
  }
}

TEST(RayCaster, FanEqualsOneCastPerBeam) {
  std::mt19937_64 rng(5);
  const OccupancyGrid grid = random_grid(rng, 400, 300, 150);
  const RayCaster caster(grid);
  std::uniform_real_distribution<double> x_of(-2.0, 20.0);
  std::uniform_real_distribution<double> y_of(1.0, 18.0);
  std::uniform_real_distribution<double> angle_of(-kPi, kPi);
  for (int scan = 0; scan < 50; ++scan) {
    const geometry::Point2D from{x_of(rng), y_of(rng)};
    const double first = angle_of(rng);
    std::vector<double> fan(361);
    caster.cast_fan(from, first, kPi / 360, 25.0, fan);
    for (std::size_t i = 0; i < fan.size(); ++i) {
      const auto single = caster.cast(from, first + static_cast<double>(i) * kPi / 360, 25.0);
      if (single) {
        ASSERT_NEAR(fan[i], *single, 1e-6) << "scan " << scan << " beam " << i;
      } else {
        ASSERT_EQ(fan[i], std::numeric_limits<double>::infinity())
            << "scan " << scan << " beam " << i;
      }
    }
  }
}

// The reference itself against dense sampling: free up to the hit, blocked just after it.
TEST(RayCaster, CellByCellAgreesWithDenseSampling) {
  std::mt19937_64 rng(11);
  const OccupancyGrid grid = random_grid(rng, 200, 200, 200);
  const RayCaster caster(grid);
  std::uniform_real_distribution<double> x_of(-0.9, 8.9);
  std::uniform_real_distribution<double> y_of(2.1, 11.9);
  std::uniform_real_distribution<double> angle_of(-kPi, kPi);
  const auto blocked = [&grid](double x, double y) {
    const auto cell = grid.cell_at({x, y});
    return cell && grid.is_occupied(*cell);
  };
  for (int i = 0; i < 300; ++i) {
    const geometry::Point2D from{x_of(rng), y_of(rng)};
    if (blocked(from.x, from.y)) continue;
    const double angle = angle_of(rng);
    const auto hit = caster.cast_cell_by_cell(from, angle, 20.0);
    const double end = hit ? *hit - 1e-7 : 20.0;
    for (double t = 0.0; t < end; t += 0.0005) {
      ASSERT_FALSE(blocked(from.x + t * std::cos(angle), from.y + t * std::sin(angle)))
          << "ray " << i << " passes a wall at " << t;
    }
    if (hit) {
      const double after = *hit + 1e-7;
      EXPECT_TRUE(blocked(from.x + after * std::cos(angle), from.y + after * std::sin(angle)));
    }
  }
}

}  // namespace
}  // namespace mobot::sim
