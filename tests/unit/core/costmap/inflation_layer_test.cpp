#include "core/costmap/inflation_layer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace mobot::costmap {
namespace {

using planning::PlanningGrid;

// The cost every cell should get, by brute force: the exact distance to the nearest source.
PlanningGrid brute_force(const PlanningGrid& input, const InflationLayer& layer) {
  PlanningGrid out = input;
  const bool unknown_source = layer.options().inflate_unknown;
  for (int y = 0; y < input.height(); ++y) {
    for (int x = 0; x < input.width(); ++x) {
      const std::uint8_t here = input.cost({x, y});
      if (here == PlanningGrid::kUnknown) continue;
      double best = std::numeric_limits<double>::infinity();
      for (int sy = 0; sy < input.height(); ++sy) {
        for (int sx = 0; sx < input.width(); ++sx) {
          const std::uint8_t c = input.cost({sx, sy});
          if (c == PlanningGrid::kLethal || (unknown_source && c == PlanningGrid::kUnknown)) {
            best = std::min(best, std::hypot(sx - x, sy - y) * input.resolution_m());
          }
        }
      }
      const std::uint8_t inflated = layer.cost_at_distance(best);
      out.set_cost({x, y}, std::max(here, inflated));
    }
  }
  return out;
}

PlanningGrid random_grid(std::uint32_t seed, int width, int height, double lethal_fraction,
                         double unknown_fraction) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  PlanningGrid grid(width, height, 0.05, {1.0, -2.0, 0.3});
  for (auto& cost : grid.mutable_costs()) {
    const double u = unit(rng);
    cost = u < lethal_fraction                      ? PlanningGrid::kLethal
           : u < lethal_fraction + unknown_fraction ? PlanningGrid::kUnknown
           : u < 0.9                                ? PlanningGrid::kFree
                                                    : static_cast<std::uint8_t>(rng() % 200);
  }
  return grid;
}

TEST(InflationLayer, MatchesTheExactEuclideanDistanceEverywhere) {
  for (const bool inflate_unknown : {false, true}) {
    for (std::uint32_t seed = 1; seed <= 4; ++seed) {
      InflationLayerOptions options;
      options.inscribed_radius_m = 0.1 + 0.05 * seed;
      options.inflation_radius_m = options.inscribed_radius_m + 0.2;
      options.inflate_unknown = inflate_unknown;
      InflationLayer layer(options);
      const PlanningGrid input = random_grid(seed, 37, 29, 0.01 * seed, 0.01);
      PlanningGrid fast = input;
      layer.inflate(fast, CellBounds::of_size(fast.width(), fast.height()));
      const PlanningGrid expected = brute_force(input, layer);
      ASSERT_EQ(fast.costs(), expected.costs())
          << "seed " << seed << " unknown " << inflate_unknown;
    }
  }
}

TEST(InflationLayer, WritesCostmapValuesAroundOneObstacle) {
  InflationLayer layer;  // the Dashgo: inscribed 0.2 m, radius 0.25 m, scaling 10
  PlanningGrid grid(31, 31, 0.05, {});
  grid.set_cost({15, 15}, PlanningGrid::kLethal);
  layer.inflate(grid, CellBounds::of_size(31, 31));
  EXPECT_EQ(grid.cost({15, 15}), PlanningGrid::kLethal);
  for (int d = 1; d <= 4; ++d) EXPECT_EQ(grid.cost({15 + d, 15}), PlanningGrid::kInscribed) << d;
  // 0.25 m: 252 exp(-10 x 0.05) = 152.8.
  EXPECT_EQ(grid.cost({20, 15}), 153);
  EXPECT_EQ(grid.cost({15, 10}), 153);
  EXPECT_EQ(grid.cost({21, 15}), PlanningGrid::kFree);
  // (3, 3) cells: 0.212 m, in the band: 252 exp(-10 x 0.0121) = 223.
  EXPECT_EQ(grid.cost({18, 18}),
            std::lround(252.0 * std::exp(-10.0 * (std::hypot(0.15, 0.15) - 0.2))));
}

TEST(InflationLayer, CostFallsWithDistanceAndEndsAtTheRadius) {
  const InflationLayer layer;
  std::uint8_t previous = PlanningGrid::kLethal;
  for (double d = 0.0; d < 0.4; d += 0.005) {
    EXPECT_LE(layer.cost_at_distance(d), previous) << d;
    previous = layer.cost_at_distance(d);
  }
  EXPECT_EQ(layer.cost_at_distance(0.0), PlanningGrid::kLethal);
  EXPECT_EQ(layer.cost_at_distance(0.2), PlanningGrid::kInscribed);
  EXPECT_EQ(layer.cost_at_distance(0.2001), 252);
  EXPECT_EQ(layer.cost_at_distance(0.2501), PlanningGrid::kFree);
  EXPECT_EQ(layer.reach_cells(0.05), 6);
  EXPECT_EQ(layer.reach_cells(0.1), 4);
}

TEST(InflationLayer, InflatingPartOfTheGridReadsObstaclesOutsideIt) {
  const InflationLayer reference;
  PlanningGrid input(40, 40, 0.05, {});
  input.set_cost({10, 20}, PlanningGrid::kLethal);
  input.set_cost({25, 22}, PlanningGrid::kLethal);
  PlanningGrid whole = input;
  InflationLayer(reference.options()).inflate(whole, CellBounds::of_size(40, 40));
  // Bounds that hold neither obstacle but cells both inflate.
  const CellBounds part{12, 15, 22, 25};
  PlanningGrid partial = input;
  InflationLayer(reference.options()).inflate(partial, part);
  for (int y = 0; y < 40; ++y) {
    for (int x = 0; x < 40; ++x) {
      const std::uint8_t expected = part.contains({x, y}) ? whole.cost({x, y}) : input.cost({x, y});
      ASSERT_EQ(partial.cost({x, y}), expected) << x << "," << y;
    }
  }
  EXPECT_GT(partial.cost({12, 20}), PlanningGrid::kFree);
}

TEST(InflationLayer, NeverLowersACostAndLeavesUnknownCellsUnknown) {
  PlanningGrid grid(20, 5, 0.05, {});
  grid.set_cost({0, 2}, PlanningGrid::kLethal);
  grid.set_cost({3, 2}, PlanningGrid::kUnknown);
  grid.set_cost({10, 2}, 200);  // written by a layer below: stays
  InflationLayer().inflate(grid, CellBounds::of_size(20, 5));
  EXPECT_EQ(grid.cost({3, 2}), PlanningGrid::kUnknown);
  EXPECT_EQ(grid.cost({10, 2}), 200);
  EXPECT_EQ(grid.cost({2, 2}), PlanningGrid::kInscribed);
}

TEST(InflationLayer, UnknownCellsInflateOnlyWhenAsked) {
  PlanningGrid grid(20, 3, 0.05, {});
  grid.set_cost({0, 1}, PlanningGrid::kUnknown);
  PlanningGrid plain = grid;
  InflationLayer().inflate(plain, CellBounds::of_size(20, 3));
  EXPECT_EQ(plain.cost({2, 1}), PlanningGrid::kFree);
  InflationLayerOptions options;
  options.inflate_unknown = true;
  InflationLayer(options).inflate(grid, CellBounds::of_size(20, 3));
  EXPECT_EQ(grid.cost({0, 1}), PlanningGrid::kUnknown);
  EXPECT_EQ(grid.cost({2, 1}), PlanningGrid::kInscribed);
}

TEST(InflationLayer, GrowsTheUpdateBoundsByItsReach) {
  InflationLayer layer;
  const PlanningGrid master(100, 100, 0.05, {});
  CellBounds bounds{40, 40, 41, 41};
  layer.update_bounds(master, bounds);
  EXPECT_EQ(bounds, (CellBounds{34, 34, 47, 47}));
  CellBounds nothing;
  layer.update_bounds(master, nothing);
  EXPECT_TRUE(nothing.empty());
}

TEST(InflationLayer, EmptyBoundsAndObstacleFreeGridsChangeNothing) {
  PlanningGrid grid(10, 10, 0.05, {});
  InflationLayer layer;
  layer.inflate(grid, {});
  layer.inflate(grid, CellBounds::of_size(10, 10));
  for (const auto cost : grid.costs()) EXPECT_EQ(cost, PlanningGrid::kFree);
  layer.inflate(grid, CellBounds{20, 20, 30, 30});  // off the grid
}

TEST(InflationLayer, RejectsBadOptions) {
  InflationLayerOptions options;
  options.inscribed_radius_m = std::nan("");
  EXPECT_THROW(InflationLayer{options}, std::invalid_argument);
  options = {};
  options.inflation_radius_m = -0.1;
  EXPECT_THROW(InflationLayer{options}, std::invalid_argument);
  options = {};
  options.cost_scaling_per_m = std::numeric_limits<double>::infinity();
  EXPECT_THROW(InflationLayer{options}, std::invalid_argument);
  // A radius inside the inscribed one: no band, still valid.
  options = {};
  options.inflation_radius_m = 0.1;
  const InflationLayer no_band(options);
  EXPECT_EQ(no_band.cost_at_distance(0.15), PlanningGrid::kInscribed);
  EXPECT_EQ(no_band.cost_at_distance(0.21), PlanningGrid::kFree);
}

}  // namespace
}  // namespace mobot::costmap
