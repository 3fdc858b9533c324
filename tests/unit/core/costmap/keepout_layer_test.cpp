#include "core/costmap/keepout_layer.h"

#include <gtest/gtest.h>

#include <limits>

namespace mobot::costmap {
namespace {

using planning::PlanningGrid;

PlanningGrid written(KeepoutLayer& layer, PlanningGrid master) {
  CellBounds bounds;
  layer.update_bounds(master, bounds);
  if (!bounds.empty()) layer.update(master, bounds.clipped(master.width(), master.height()));
  return master;
}

TEST(KeepoutLayer, RasterisesAZoneAsLethal) {
  KeepoutLayer layer;
  ASSERT_FALSE(layer.set_zones({{{1.0, 1.0}, {2.0, 1.0}, {2.0, 2.0}, {1.0, 2.0}}}).has_value());
  const PlanningGrid master = written(layer, PlanningGrid(60, 60, 0.05, {}));
  EXPECT_EQ(master.cost(*master.cell_at({1.5, 1.5})), PlanningGrid::kLethal);
  EXPECT_EQ(master.cost(*master.cell_at({1.025, 1.975})), PlanningGrid::kLethal);
  EXPECT_EQ(master.cost(*master.cell_at({0.9, 1.5})), PlanningGrid::kFree);
  EXPECT_EQ(master.cost(*master.cell_at({2.1, 1.5})), PlanningGrid::kFree);
  int lethal = 0;
  for (const auto cost : master.costs()) lethal += cost == PlanningGrid::kLethal;
  EXPECT_GE(lethal, 400);
  EXPECT_LE(lethal, 21 * 21);
}

TEST(KeepoutLayer, AZoneThinnerThanACellStillBlocks) {
  KeepoutLayer layer;
  // A 1 cm wide sliver across the grid: no cell centre inside, its edges cross 40 cells.
  ASSERT_FALSE(layer.set_zones({{{0.0, 1.01}, {2.0, 1.01}, {2.0, 1.02}, {0.0, 1.02}}}).has_value());
  const PlanningGrid master = written(layer, PlanningGrid(40, 40, 0.05, {}));
  for (int x = 0; x < 40; ++x) EXPECT_EQ(master.cost({x, 20}), PlanningGrid::kLethal) << x;
  EXPECT_EQ(master.cost({5, 19}), PlanningGrid::kFree);
}

TEST(KeepoutLayer, RefusesABadZoneAndKeepsThePreviousOnes) {
  KeepoutLayer layer;
  ASSERT_FALSE(layer.set_zones({{{1.0, 1.0}, {2.0, 1.0}, {2.0, 2.0}}}).has_value());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(layer.set_zones({{{0, 0}, {1, 0}, {0, 1}}, {{0, 0}, {1, 1}, {1, 0}, {0, 1}}}),
            "zone 1: edge 0-1 meets edge 2-3 (the polygon intersects itself)");
  EXPECT_EQ(layer.set_zones({{{0, 0}, {nan, 0}, {0, 1}}}), "zone 0: vertex 1 is not finite");
  EXPECT_EQ(layer.set_zones({{{0, 0}, {1, 0}}}),
            "zone 0: a polygon needs 3 to 256 vertices, got 2");
  ASSERT_EQ(layer.zones().size(), 1U);
  KeepoutLayerOptions options;
  options.max_zones = 1;
  KeepoutLayer small(options);
  EXPECT_EQ(small.set_zones({{{0, 0}, {1, 0}, {0, 1}}, {{0, 0}, {1, 0}, {0, 1}}}),
            "at most 1 keep-out zones, got 2");
}

TEST(KeepoutLayer, ClearingTheZonesFreesTheCells) {
  KeepoutLayer layer;
  layer.set_zones({{{1.0, 1.0}, {2.0, 1.0}, {2.0, 2.0}, {1.0, 2.0}}});
  PlanningGrid master(60, 60, 0.05, {});
  master = written(layer, master);
  ASSERT_FALSE(layer.set_zones({}).has_value());
  PlanningGrid reset(60, 60, 0.05, {});
  reset = written(layer, reset);
  for (const auto cost : reset.costs()) EXPECT_EQ(cost, PlanningGrid::kFree);
}

}  // namespace
}  // namespace mobot::costmap
