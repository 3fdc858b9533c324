#include "core/estimation/particle_filter/likelihood_field.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

namespace mobot::estimation {
namespace {

using mapping::CellIndex;
using mapping::OccupancyGrid;

// The distance of every cell centre to the nearest occupied cell centre, by looking at all.
double brute_force_distance(const OccupancyGrid& grid, CellIndex cell, double cap_m) {
  double best = std::numeric_limits<double>::infinity();
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      if (!grid.is_occupied({x, y})) continue;
      best = std::min(best, std::hypot(x - cell.x, y - cell.y) * grid.resolution_m());
    }
  }
  return std::min(best, cap_m);
}

OccupancyGrid random_grid(std::uint64_t seed) {
  OccupancyGrid grid(47, 31, 0.1, {-1.0, 2.0, 0.0}, OccupancyGrid::kFree);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> value(0, 99);
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const int v = value(rng);
      // A few obstacles (some at the threshold, some just below it), unknown patches.
      if (v < 2)
        grid.set({x, y}, OccupancyGrid::kOccupied);
      else if (v < 3)
        grid.set({x, y}, OccupancyGrid::kOccupiedThreshold);
      else if (v < 5)
        grid.set({x, y}, OccupancyGrid::kOccupiedThreshold - 1);
      else if (v < 20)
        grid.set({x, y}, OccupancyGrid::kUnknown);
    }
  }
  return grid;
}

TEST(LikelihoodField, MatchesABruteForceDistanceCappedAtTheMaximum) {
  for (std::uint64_t seed : {1U, 2U, 3U}) {
    const OccupancyGrid grid = random_grid(seed);
    const LikelihoodField field(grid, {0.7});
    ASSERT_TRUE(field.has_obstacles());
    ASSERT_EQ(field.width(), grid.width());
    ASSERT_EQ(field.height(), grid.height());
    double largest = 0.0;
    for (int y = 0; y < grid.height(); ++y) {
      for (int x = 0; x < grid.width(); ++x) {
        const double expected = brute_force_distance(grid, {x, y}, 0.7);
        ASSERT_NEAR(field.distance_at({x, y}), expected, 1e-5) << x << "," << y;
        largest = std::max(largest, expected);
      }
    }
    // The cap is reached somewhere, so the comparison covered capped cells too.
    EXPECT_DOUBLE_EQ(largest, 0.7);
  }
}

TEST(LikelihoodField, UnknownCellsAreNotObstacles) {
  OccupancyGrid grid(20, 20, 0.05, {}, OccupancyGrid::kUnknown);
  grid.set({10, 10}, OccupancyGrid::kOccupied);
  const LikelihoodField field(grid);
  EXPECT_EQ(field.distance_at({10, 10}), 0.0);
  EXPECT_NEAR(field.distance_at({13, 14}), 0.25, 1e-6);  // a 3-4-5 triangle of 5 cm cells
  EXPECT_NEAR(field.distance_at({0, 10}), 0.5, 1e-6);
}

TEST(LikelihoodField, PointsOffTheGridOrNotFiniteAreFarFromEverything) {
  OccupancyGrid grid(10, 10, 0.1, {2.0, 3.0, 0.0}, OccupancyGrid::kFree);
  grid.set({0, 0}, OccupancyGrid::kOccupied);
  const LikelihoodField field(grid, {1.5});
  EXPECT_EQ(field.distance_m({2.05, 3.05}), 0.0);
  EXPECT_NEAR(field.distance_m({2.35, 3.05}), 0.3, 1e-6);
  EXPECT_EQ(field.distance_m({1.99, 3.05}), 1.5);
  EXPECT_EQ(field.distance_m({2.05, 4.01}), 1.5);
  EXPECT_EQ(field.distance_m({std::numeric_limits<double>::quiet_NaN(), 3.05}), 1.5);
  EXPECT_EQ(field.distance_at({-1, 0}), 1.5);
  EXPECT_EQ(field.distance_at({0, 10}), 1.5);
}

TEST(LikelihoodField, OpenWhereObservedAndNotOccupied) {
  OccupancyGrid grid(10, 10, 0.1, {2.0, 3.0, 0.0}, OccupancyGrid::kFree);
  grid.set({0, 0}, OccupancyGrid::kOccupied);
  grid.set({1, 0}, OccupancyGrid::kUnknown);
  grid.set({2, 0}, 64);  // below the occupied threshold
  const LikelihoodField field(grid);
  EXPECT_FALSE(field.open_at({2.05, 3.05}));
  EXPECT_FALSE(field.open_at({2.15, 3.05}));
  EXPECT_TRUE(field.open_at({2.25, 3.05}));
  EXPECT_TRUE(field.open_at({2.55, 3.55}));
  EXPECT_FALSE(field.open_at({1.99, 3.05}));  // off the grid
  EXPECT_FALSE(field.open_at({2.05, 4.01}));
  EXPECT_FALSE(field.open_at({std::numeric_limits<double>::quiet_NaN(), 3.05}));
}

TEST(LikelihoodField, FollowsARotatedOrigin) {
  // A grid whose x axis points along the map's y axis.
  OccupancyGrid grid(10, 10, 0.1, {1.0, 1.0, std::numbers::pi / 2.0}, OccupancyGrid::kFree);
  grid.set({5, 0}, OccupancyGrid::kOccupied);
  const LikelihoodField field(grid);
  const geometry::Point2D centre = grid.cell_center({5, 0});
  EXPECT_EQ(field.distance_m(centre), 0.0);
  EXPECT_NEAR(field.distance_m(grid.cell_center({5, 3})), 0.3, 1e-6);
}

TEST(LikelihoodField, AMapWithoutObstaclesIsEverywhereAtTheMaximum) {
  const OccupancyGrid grid(8, 6, 0.05, {}, OccupancyGrid::kFree);
  const LikelihoodField field(grid, {2.0});
  EXPECT_FALSE(field.has_obstacles());
  EXPECT_TRUE(std::all_of(field.distances_m().begin(), field.distances_m().end(),
                          [](float d) { return d == 2.0F; }));
  const LikelihoodField empty{OccupancyGrid{}};
  EXPECT_EQ(empty.width(), 0);
  EXPECT_EQ(empty.distance_m({0.0, 0.0}), 2.0);
}

TEST(LikelihoodField, RefusesABadMaximumDistance) {
  const OccupancyGrid grid(4, 4, 0.05, {});
  EXPECT_THROW(LikelihoodField(grid, {0.0}), std::invalid_argument);
  EXPECT_THROW(LikelihoodField(grid, {-1.0}), std::invalid_argument);
  EXPECT_THROW(LikelihoodField(grid, {std::numeric_limits<double>::infinity()}),
               std::invalid_argument);
  EXPECT_THROW(LikelihoodField(grid, {std::numeric_limits<double>::quiet_NaN()}),
               std::invalid_argument);
}

}  // namespace
}  // namespace mobot::estimation
