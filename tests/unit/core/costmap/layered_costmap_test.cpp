#include "core/costmap/layered_costmap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "core/costmap/inflation_layer.h"
#include "core/costmap/keepout_layer.h"
#include "core/costmap/obstacle_layer.h"
#include "core/costmap/range_sensor_layer.h"
#include "core/costmap/static_layer.h"
#include "core/planning/planning_grid_builder.h"

namespace mobot::costmap {
namespace {

using mapping::OccupancyGrid;
using planning::PlanningGrid;

// 8 x 6 m at 0.05 m: outer walls, an inner wall with a door, a pillar and an unknown corner.
OccupancyGrid room() {
  OccupancyGrid map(160, 120, 0.05, {-1.0, -1.0, 0.0}, OccupancyGrid::kFree);
  const auto fill = [&](int x0, int y0, int x1, int y1, std::uint8_t value) {
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) map.set({x, y}, value);
    }
  };
  fill(0, 0, 159, 1, OccupancyGrid::kOccupied);
  fill(0, 118, 159, 119, OccupancyGrid::kOccupied);
  fill(0, 0, 1, 119, OccupancyGrid::kOccupied);
  fill(158, 0, 159, 119, OccupancyGrid::kOccupied);
  fill(80, 0, 81, 70, OccupancyGrid::kOccupied);
  fill(80, 95, 81, 119, OccupancyGrid::kOccupied);
  fill(40, 40, 44, 44, OccupancyGrid::kOccupied);
  fill(140, 100, 157, 117, OccupancyGrid::kUnknown);
  return map;
}

msgs::LaserScan ring_scan(int beams, float range_m) {
  msgs::LaserScan scan;
  scan.angle_min_rad = static_cast<float>(-std::numbers::pi);
  scan.angle_increment_rad = static_cast<float>(2.0 * std::numbers::pi / beams);
  scan.range_min_m = 0.05F;
  scan.range_max_m = 10.0F;
  scan.ranges_m.assign(static_cast<std::size_t>(beams), range_m);
  return scan;
}

InflationLayerOptions builder_like_inflation() {
  InflationLayerOptions options;
  options.inscribed_radius_m = 0.3;
  options.inflation_radius_m = 0.55;
  options.inflate_unknown = true;
  return options;
}

TEST(LayeredCostmap, AGlobalCostmapOfStaticAndInflationIsThePlanningGrid) {
  const OccupancyGrid map = room();
  LayeredCostmap costmap;
  costmap.add(std::make_unique<StaticLayer>()).set_map(map);
  costmap.add(std::make_unique<InflationLayer>(builder_like_inflation()));
  costmap.resize_to(map);
  const CellBounds bounds = costmap.update({});
  EXPECT_EQ(bounds, CellBounds::of_size(160, 120));
  const PlanningGrid expected = planning::PlanningGridBuilder().build(map);
  EXPECT_EQ(costmap.master().costs(), expected.costs());
  EXPECT_EQ(costmap.master().origin(), map.origin());
  // Nothing changed: nothing recomputed.
  EXPECT_TRUE(costmap.update({}).empty());
  EXPECT_EQ(costmap.rebuild(), CellBounds::of_size(160, 120));
  EXPECT_EQ(costmap.master().costs(), expected.costs());
}

TEST(LayeredCostmap, AnObservationRecomputesOnlyAroundItAndMatchesARebuild) {
  const OccupancyGrid map = room();
  const auto make = [&map](LayeredCostmap& costmap) -> ObstacleLayer& {
    costmap.add(std::make_unique<StaticLayer>()).set_map(map);
    ObstacleLayer& laser = costmap.add(std::make_unique<ObstacleLayer>());
    costmap.add(std::make_unique<InflationLayer>(builder_like_inflation()));
    costmap.resize_to(map);
    return laser;
  };
  LayeredCostmap incremental;
  ObstacleLayer& laser = make(incremental);
  incremental.update({});
  const geometry::Pose2D sensor{5.0, 3.0, 0.0};
  ASSERT_TRUE(laser.add_scan(ring_scan(360, 0.8F), sensor));
  const CellBounds bounds = incremental.update(sensor);
  EXPECT_FALSE(bounds.empty());
  EXPECT_LE(bounds.width(), 2 * 17 + 2 * 12 + 2);  // the scan's circle plus the inflation reach
  EXPECT_LT(bounds.cell_count(), 160U * 120U / 4);

  LayeredCostmap fresh;
  ObstacleLayer& fresh_laser = make(fresh);
  fresh_laser.add_scan(ring_scan(360, 0.8F), sensor);
  fresh.update(sensor);
  EXPECT_EQ(incremental.master().costs(), fresh.master().costs());
  EXPECT_EQ(incremental.master().cost(*incremental.master().cell_at({5.79, 3.0})),
            PlanningGrid::kLethal);
}

TEST(LayeredCostmap, ARollingWindowStaysCentredOnTheRobot) {
  LayeredCostmapOptions options;
  options.rolling = true;
  LayeredCostmap costmap(options);
  EXPECT_TRUE(costmap.master().empty());
  costmap.update({5.0, 5.0, 1.0});
  ASSERT_EQ(costmap.master().width(), 60);
  ASSERT_EQ(costmap.master().height(), 60);
  EXPECT_NEAR(costmap.master().origin().x, 3.5, 1e-9);
  EXPECT_NEAR(costmap.master().origin().y, 3.5, 1e-9);
  EXPECT_EQ(costmap.master().origin().theta, 0.0);
  costmap.update({5.32, 4.87, -2.0});
  EXPECT_NEAR(costmap.master().origin().x, 3.8, 1e-9);
  EXPECT_NEAR(costmap.master().origin().y, 3.35, 1e-9);
  // Far away: a new window.
  costmap.update({50.0, -20.0, 0.0});
  EXPECT_NEAR(costmap.master().origin().x, 48.5, 1e-9);
  EXPECT_NEAR(costmap.master().origin().y, -21.5, 1e-9);
}

TEST(LayeredCostmap, AShiftedWindowEqualsOneComputedFromScratch) {
  const OccupancyGrid map = room();
  LayeredCostmapOptions options;
  options.rolling = true;
  options.lattice_origin_m = {map.origin().x, map.origin().y};
  const auto make = [&](LayeredCostmap& costmap) -> ObstacleLayer& {
    costmap.add(std::make_unique<StaticLayer>()).set_map(map);
    ObstacleLayer& laser = costmap.add(std::make_unique<ObstacleLayer>());
    KeepoutLayer& keepout = costmap.add(std::make_unique<KeepoutLayer>());
    EXPECT_FALSE(keepout.set_zones({{{2.6, 1.2}, {3.2, 1.2}, {3.2, 1.6}}}).has_value());
    costmap.add(std::make_unique<InflationLayer>());
    return laser;
  };
  // Scans of 1 m from the first pose stay inside both windows, so both costmaps saw the same.
  const geometry::Pose2D first{2.0, 2.0, 0.0};
  const geometry::Pose2D second{2.37, 1.76, 0.5};
  LayeredCostmap moving(options);
  ObstacleLayer& laser = make(moving);
  laser.add_scan(ring_scan(720, 1.0F), first);
  moving.update(first);
  laser.add_scan(ring_scan(720, 0.6F), second);
  moving.update(second);

  LayeredCostmap fresh(options);
  ObstacleLayer& fresh_laser = make(fresh);
  // The same scans in the same order, but in the window where `moving` ended from the start.
  fresh_laser.add_scan(ring_scan(720, 1.0F), first);
  fresh.update(second);
  fresh_laser.add_scan(ring_scan(720, 0.6F), second);
  fresh.update(second);
  ASSERT_EQ(moving.master().origin(), fresh.master().origin());
  EXPECT_EQ(moving.master().costs(), fresh.master().costs());
  // The second scan's circle is lethal; inside it, cells the first scan marked were cleared.
  EXPECT_EQ(moving.master().cost(*moving.master().cell_at({2.97, 1.76})), PlanningGrid::kLethal);
  // The keep-out zone and the map's pillar are in the window.
  EXPECT_EQ(moving.master().cost(*moving.master().cell_at({3.0, 1.3})), PlanningGrid::kLethal);
  EXPECT_EQ(moving.master().cost(*moving.master().cell_at({1.1, 1.1})), PlanningGrid::kLethal);
}

TEST(LayeredCostmap, AStraightMoveRecomputesTheCellsThatEnteredAndWhatTheirInflationReaches) {
  LayeredCostmapOptions options;
  options.rolling = true;
  LayeredCostmap costmap(options);
  costmap.add(std::make_unique<ObstacleLayer>());
  costmap.add(std::make_unique<InflationLayer>());  // reach 6 cells at 0.05 m
  EXPECT_EQ(costmap.update({0.0, 0.0, 0.0}), CellBounds::of_size(60, 60));
  EXPECT_TRUE(costmap.update({0.01, 0.0, 0.0}).empty());  // within the same cell
  EXPECT_EQ(costmap.update({0.35, 0.0, 0.0}), (CellBounds{60 - 7 - 6, 0, 59, 59}));
}

TEST(LayeredCostmap, TheLaserNeverClearsWhatOnlyTheInfraredRingSaw) {
  LayeredCostmapOptions options;
  options.rolling = true;
  LayeredCostmap costmap(options);
  ObstacleLayerOptions laser_options;
  laser_options.name = "laser";
  laser_options.height_band = {0.15, 0.25};
  ObstacleLayer& laser = costmap.add(std::make_unique<ObstacleLayer>(laser_options));
  RangeSensorLayerOptions ir_options;
  ir_options.name = "ir";
  ir_options.height_band = {0.6, 0.8};
  RangeSensorLayer& ir = costmap.add(std::make_unique<RangeSensorLayer>(ir_options));
  const geometry::Pose2D robot{0.0, 0.0, 0.0};
  // A table top 0.5 m ahead, seen by an upward IR sensor; the laser passes under it to a wall.
  msgs::RangeReading table;
  table.cone_rad = 0.05;
  table.range_max_m = 0.8;
  table.range_m = 0.5;
  ir.add_readings(std::vector{table}, robot);
  costmap.update(robot);
  const mapping::CellIndex table_cell = *costmap.master().cell_at({0.5, 0.0});
  ASSERT_EQ(costmap.master().cost(table_cell), PlanningGrid::kLethal);
  for (int i = 0; i < 5; ++i) {
    msgs::LaserScan scan = ring_scan(1, 1.4F);
    scan.angle_min_rad = 0.0F;
    laser.add_scan(scan, robot);
    costmap.update(robot);
  }
  EXPECT_EQ(laser.observed().cost(table_cell), PlanningGrid::kFree);
  EXPECT_EQ(costmap.master().cost(table_cell), PlanningGrid::kLethal);
  EXPECT_EQ(costmap.find("laser")->height_band(), (HeightBand{0.15, 0.25}));
  EXPECT_EQ(costmap.find("ir")->height_band(), (HeightBand{0.6, 0.8}));
  EXPECT_EQ(costmap.find("sonar"), nullptr);
}

TEST(LayeredCostmap, CellsEnteringTheWindowAreFreeOrUnknownByOption) {
  for (const bool track_unknown : {false, true}) {
    LayeredCostmapOptions options;
    options.rolling = true;
    options.track_unknown_space = track_unknown;
    LayeredCostmap costmap(options);
    costmap.add(std::make_unique<InflationLayer>());
    costmap.update({0.0, 0.0, 0.0});
    costmap.update({0.5, 0.0, 0.0});
    const std::uint8_t expected = track_unknown ? PlanningGrid::kUnknown : PlanningGrid::kFree;
    EXPECT_EQ(costmap.default_cost(), expected);
    EXPECT_EQ(costmap.master().cost({59, 30}), expected);
    EXPECT_EQ(costmap.master().cost({0, 0}), expected);
  }
}

TEST(LayeredCostmap, RefusesBadUseAndIgnoresABadPose) {
  LayeredCostmapOptions options;
  options.rolling = true;
  options.resolution_m = 0.0;
  EXPECT_THROW(LayeredCostmap{options}, std::invalid_argument);
  options.resolution_m = 0.05;
  options.width_m = std::numeric_limits<double>::infinity();
  EXPECT_THROW(LayeredCostmap{options}, std::invalid_argument);
  options.width_m = 3.0;
  options.lattice_origin_m = {std::nan(""), 0.0};
  EXPECT_THROW(LayeredCostmap{options}, std::invalid_argument);
  options.lattice_origin_m = {};
  LayeredCostmap rolling(options);
  EXPECT_THROW(rolling.resize(10, 10, 0.05, {}), std::logic_error);
  rolling.add(std::make_unique<ObstacleLayer>());
  EXPECT_THROW(rolling.add(std::make_unique<ObstacleLayer>()), std::logic_error);
  EXPECT_THROW(rolling.add_layer(nullptr), std::logic_error);
  rolling.update({1.0, 1.0, 0.0});
  const auto before = rolling.master();
  EXPECT_TRUE(rolling.update({std::nan(""), 1.0, 0.0}).empty());
  EXPECT_EQ(rolling.master().origin(), before.origin());

  LayeredCostmap global;
  EXPECT_TRUE(global.update({}).empty());  // no geometry yet
  EXPECT_THROW(global.resize(0, 10, 0.05, {}), std::invalid_argument);
  EXPECT_THROW(global.resize(10, 10, 0.05, {std::nan(""), 0.0, 0.0}), std::invalid_argument);
}

TEST(LayeredCostmap, ASnapshotIsACopy) {
  LayeredCostmap costmap;
  costmap.resize(10, 10, 0.05, {});
  costmap.update({});
  const auto snapshot = costmap.snapshot();
  ASSERT_NE(snapshot, nullptr);
  EXPECT_EQ(snapshot->costs(), costmap.master().costs());
  EXPECT_NE(snapshot.get(), &costmap.master());
}

}  // namespace
}  // namespace mobot::costmap
