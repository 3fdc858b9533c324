#include "core/estimation/particle_filter/free_space_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace mobot::estimation {
namespace {

using mapping::OccupancyGrid;

TEST(FreeSpaceSampler, SamplesOnlyObservedFreeCellsWithAnyHeading) {
  OccupancyGrid grid(10, 10, 0.1, {1.0, 2.0, 0.0}, OccupancyGrid::kUnknown);
  grid.set({2, 3}, OccupancyGrid::kFree);
  grid.set({7, 8}, 19);  // map_server's free threshold
  grid.set({5, 5}, 20);  // not free: uncertain
  grid.set({6, 6}, OccupancyGrid::kOccupied);
  const FreeSpaceSampler sampler(grid);
  ASSERT_EQ(sampler.free_cell_count(), 2U);
  std::mt19937_64 rng(1);
  int in_first = 0;
  double heading_sum_sin = 0.0;
  double heading_sum_cos = 0.0;
  for (int i = 0; i < 4000; ++i) {
    const geometry::Pose2D p = sampler.sample(rng);
    const auto cell = grid.cell_at({p.x, p.y});
    ASSERT_TRUE(cell.has_value());
    ASSERT_TRUE(*cell == (mapping::CellIndex{2, 3}) || *cell == (mapping::CellIndex{7, 8}));
    in_first += *cell == mapping::CellIndex{2, 3};
    ASSERT_GE(p.theta, -std::numbers::pi);
    ASSERT_LE(p.theta, std::numbers::pi);
    heading_sum_sin += std::sin(p.theta);
    heading_sum_cos += std::cos(p.theta);
  }
  EXPECT_NEAR(in_first, 2000, 150);
  // Uniform headings: the mean resultant is near zero.
  EXPECT_LT(std::hypot(heading_sum_sin, heading_sum_cos) / 4000.0, 0.05);
}

TEST(FreeSpaceSampler, AMapWithoutFreeCellsIsEmpty) {
  const FreeSpaceSampler unknown(OccupancyGrid(5, 5, 0.1, {}, OccupancyGrid::kUnknown));
  EXPECT_TRUE(unknown.empty());
  const FreeSpaceSampler occupied(OccupancyGrid(5, 5, 0.1, {}, OccupancyGrid::kOccupied));
  EXPECT_TRUE(occupied.empty());
  EXPECT_TRUE(FreeSpaceSampler(OccupancyGrid{}).empty());
  std::mt19937_64 rng(1);
  EXPECT_EQ(unknown.sample(rng), geometry::Pose2D{});
}

TEST(FreeSpaceSampler, ARotatedGridPutsSamplesInItsCells) {
  OccupancyGrid grid(4, 4, 0.5, {0.0, 0.0, std::numbers::pi / 2.0}, OccupancyGrid::kUnknown);
  grid.set({1, 0}, OccupancyGrid::kFree);
  const FreeSpaceSampler sampler(grid);
  std::mt19937_64 rng(2);
  for (int i = 0; i < 100; ++i) {
    const geometry::Pose2D p = sampler.sample(rng);
    // Cell (1, 0) of a grid turned by 90 deg covers x in [-0.5, 0], y in [0.5, 1.0].
    EXPECT_LE(p.x, 1e-12);
    EXPECT_GE(p.x, -0.5);
    EXPECT_GE(p.y, 0.5);
    EXPECT_LE(p.y, 1.0);
  }
}

}  // namespace
}  // namespace mobot::estimation
