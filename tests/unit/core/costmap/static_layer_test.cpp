#include "core/costmap/static_layer.h"

#include <gtest/gtest.h>

#include <numbers>

namespace mobot::costmap {
namespace {

using mapping::OccupancyGrid;
using planning::PlanningGrid;

OccupancyGrid sample_map() {
  OccupancyGrid map(20, 10, 0.05, {1.0, 2.0, 0.0}, OccupancyGrid::kFree);
  map.set({3, 4}, OccupancyGrid::kOccupied);
  map.set({4, 4}, 64);
  map.set({5, 4}, 65);
  map.set({6, 4}, OccupancyGrid::kUnknown);
  return map;
}

void write_all(StaticLayer& layer, PlanningGrid& master) {
  CellBounds bounds;
  layer.update_bounds(master, bounds);
  ASSERT_EQ(bounds, CellBounds::of_size(master.width(), master.height()));
  layer.update(master, bounds);
}

TEST(StaticLayer, TurnsOccupancyIntoCosts) {
  StaticLayer layer;
  EXPECT_FALSE(layer.has_map());
  layer.set_map(sample_map());
  ASSERT_TRUE(layer.has_map());
  const PlanningGrid& costs = layer.map_costs();
  EXPECT_EQ(costs.cost({3, 4}), PlanningGrid::kLethal);
  EXPECT_EQ(costs.cost({4, 4}), PlanningGrid::kFree);
  EXPECT_EQ(costs.cost({5, 4}), PlanningGrid::kLethal);
  EXPECT_EQ(costs.cost({6, 4}), PlanningGrid::kUnknown);
  EXPECT_EQ(costs.origin(), sample_map().origin());
  StaticLayerOptions options;
  options.unknown_is_obstacle = false;
  options.occupied_threshold = 90;
  StaticLayer lenient(options);
  lenient.set_map(sample_map());
  EXPECT_EQ(lenient.map_costs().cost({5, 4}), PlanningGrid::kFree);
  EXPECT_EQ(lenient.map_costs().cost({6, 4}), PlanningGrid::kFree);
  EXPECT_EQ(lenient.map_costs().cost({3, 4}), PlanningGrid::kLethal);
}

TEST(StaticLayer, OverwritesAMasterOfTheMapsGeometry) {
  StaticLayer layer;
  layer.set_map(sample_map());
  PlanningGrid master(20, 10, 0.05, {1.0, 2.0, 0.0}, 200);
  write_all(layer, master);
  EXPECT_EQ(master.costs(), layer.map_costs().costs());
  // Nothing changed since: no bounds.
  CellBounds bounds;
  layer.update_bounds(master, bounds);
  EXPECT_TRUE(bounds.empty());
}

TEST(StaticLayer, CopiesIntoAWindowOnTheMapsLatticeAndLeavesOffMapCells) {
  StaticLayer layer;
  layer.set_map(sample_map());
  // A 10 x 10 window whose corner is map cell (-2, 1): its cell (5, 3) is map cell (3, 4).
  PlanningGrid window(10, 10, 0.05, {0.9, 2.05, 0.0}, 77);
  write_all(layer, window);
  EXPECT_EQ(window.cost({5, 3}), PlanningGrid::kLethal);
  EXPECT_EQ(window.cost({8, 3}), PlanningGrid::kUnknown);
  EXPECT_EQ(window.cost({0, 0}), 77);  // off the map
  EXPECT_EQ(window.cost({2, 0}), PlanningGrid::kFree);
  EXPECT_EQ(window.cost({9, 9}), 77);  // above the map's 10 rows
}

TEST(StaticLayer, ResamplesAFinerOrRotatedMaster) {
  StaticLayer layer;
  layer.set_map(sample_map());
  // Twice as fine: map cell (3, 4) covers four master cells.
  PlanningGrid fine(40, 20, 0.025, {1.0, 2.0, 0.0});
  write_all(layer, fine);
  for (const auto& [x, y] : {std::pair{6, 8}, {7, 8}, {6, 9}, {7, 9}}) {
    EXPECT_EQ(fine.cost({x, y}), PlanningGrid::kLethal);
  }
  EXPECT_EQ(fine.cost({8, 8}), PlanningGrid::kFree);
  // Rotated by 90 degrees about the map cell (3, 4)'s centre.
  layer.set_map(sample_map());
  PlanningGrid rotated(3, 3, 0.05, {1.175 + 0.075, 2.225 - 0.075, std::numbers::pi / 2});
  write_all(layer, rotated);
  EXPECT_EQ(rotated.cost({1, 1}), PlanningGrid::kLethal);
  EXPECT_EQ(rotated.cost({1, 0}), PlanningGrid::kFree);
}

TEST(StaticLayer, AnEmptyMapWritesNothing) {
  StaticLayer layer;
  layer.set_map(OccupancyGrid());
  EXPECT_FALSE(layer.has_map());
  PlanningGrid master(5, 5, 0.05, {}, 9);
  write_all(layer, master);
  for (const auto cost : master.costs()) EXPECT_EQ(cost, 9);
}

}  // namespace
}  // namespace mobot::costmap
