#include "core/costmap/obstacle_layer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace mobot::costmap {
namespace {

using planning::PlanningGrid;

// A scan of `ranges` beams spread evenly from angle_min with the given increment.
msgs::LaserScan scan(std::vector<float> ranges, float angle_min = 0.0F, float increment = 0.0F,
                     float range_max = 10.0F) {
  msgs::LaserScan out;
  out.angle_min_rad = angle_min;
  out.angle_increment_rad = increment;
  out.range_min_m = 0.05F;
  out.range_max_m = range_max;
  out.ranges_m = std::move(ranges);
  return out;
}

// A 5 x 5 m grid at 0.05 m with its origin at (0, 0); the sensor sits at its centre.
class ObstacleLayerTest : public ::testing::Test {
 protected:
  ObstacleLayerTest() : master_(100, 100, 0.05, {}) {}
  CellBounds update(ObstacleLayer& layer) {
    CellBounds bounds;
    layer.update_bounds(master_, bounds);
    return bounds;
  }
  std::uint8_t at(const ObstacleLayer& layer, double x, double y) {
    return layer.observed().cost(*master_.cell_at({x, y}));
  }
  PlanningGrid master_;
  const geometry::Pose2D sensor_{2.525, 2.525, 0.0};
};

TEST_F(ObstacleLayerTest, MarksTheReturnAndClearsTheCellsBeforeIt) {
  ObstacleLayer layer;
  ASSERT_TRUE(layer.add_scan(scan({1.0F}), sensor_));
  const CellBounds bounds = update(layer);
  EXPECT_EQ(at(layer, 3.525, 2.525), PlanningGrid::kLethal);
  for (double x = 2.525; x < 3.5; x += 0.05)
    EXPECT_EQ(at(layer, x, 2.525), PlanningGrid::kFree) << x;
  EXPECT_EQ(at(layer, 3.625, 2.525), PlanningGrid::kUnknown);  // behind the return: unseen
  EXPECT_EQ(at(layer, 2.525, 2.625), PlanningGrid::kUnknown);  // beside the beam
  EXPECT_EQ(bounds, (CellBounds{50, 50, 70, 50}));
}

TEST_F(ObstacleLayerTest, ReturnsBeyondTheObstacleRangeOnlyClear) {
  ObstacleLayerOptions options;
  options.obstacle_range_m = 0.8;
  options.raytrace_range_m = 3.0;
  ObstacleLayer layer(options);
  layer.add_scan(scan({1.0F}), sensor_);
  update(layer);
  EXPECT_EQ(at(layer, 3.525, 2.525), PlanningGrid::kFree);
  EXPECT_EQ(at(layer, 3.025, 2.525), PlanningGrid::kFree);
}

TEST_F(ObstacleLayerTest, ClearsNoFartherThanTheRaytraceRange) {
  ObstacleLayerOptions options;
  options.raytrace_range_m = 0.5;
  ObstacleLayer layer(options);
  layer.add_scan(scan({2.0F}), sensor_);
  update(layer);
  EXPECT_EQ(at(layer, 2.975, 2.525), PlanningGrid::kFree);
  EXPECT_EQ(at(layer, 3.125, 2.525), PlanningGrid::kUnknown);
  EXPECT_EQ(at(layer, 4.525, 2.525), PlanningGrid::kLethal);  // within obstacle_range 2.5
}

TEST_F(ObstacleLayerTest, ABeamWithoutReturnClearsToRangeMaxOrNothing) {
  ObstacleLayer layer;
  layer.add_scan(scan({10.0F, std::numeric_limits<float>::infinity()}, 0.0F,
                      static_cast<float>(std::numbers::pi / 2), 1.0F),
                 sensor_);
  update(layer);
  EXPECT_EQ(at(layer, 3.475, 2.525), PlanningGrid::kFree);     // cleared to range_max 1 m
  EXPECT_EQ(at(layer, 3.575, 2.525), PlanningGrid::kUnknown);  // not marked, not beyond
  EXPECT_EQ(at(layer, 2.525, 3.475), PlanningGrid::kFree);     // the infinite beam, up
  ObstacleLayerOptions options;
  options.clear_on_no_return = false;
  ObstacleLayer strict(options);
  strict.add_scan(scan({10.0F}, 0.0F, 0.0F, 1.0F), sensor_);
  update(strict);
  EXPECT_EQ(at(strict, 3.0, 2.525), PlanningGrid::kUnknown);
}

TEST_F(ObstacleLayerTest, KeepsAnObstacleUntilABeamCrossesItsCell) {
  ObstacleLayer layer;
  layer.add_scan(scan({1.0F}), sensor_);
  update(layer);
  // The next scan looks elsewhere: the obstacle stays.
  layer.add_scan(scan({1.0F}, static_cast<float>(std::numbers::pi / 2)), sensor_);
  update(layer);
  EXPECT_EQ(at(layer, 3.525, 2.525), PlanningGrid::kLethal);
  // The obstacle moved away: a longer return through its cell clears it.
  layer.add_scan(scan({2.0F}), sensor_);
  update(layer);
  EXPECT_EQ(at(layer, 3.525, 2.525), PlanningGrid::kFree);
  EXPECT_EQ(at(layer, 4.525, 2.525), PlanningGrid::kLethal);
}

TEST_F(ObstacleLayerTest, MarksAfterClearingSoOneScanNeverErasesItsOwnReturns) {
  ObstacleLayer layer;
  // Beam 0 returns at 1 m straight ahead; beam 1 (a tiny angle away) passes the same cell to 2 m.
  layer.add_scan(scan({1.0F, 2.0F}, 0.0F, 0.001F), sensor_);
  update(layer);
  EXPECT_EQ(at(layer, 3.525, 2.525), PlanningGrid::kLethal);
}

TEST_F(ObstacleLayerTest, ASensorOutsideTheGridStillClearsItsPartOfTheRay) {
  ObstacleLayer layer;
  layer.add_scan(scan({2.02F}), {-1.0, 2.525, 0.0});
  update(layer);
  EXPECT_EQ(at(layer, 0.025, 2.525), PlanningGrid::kFree);
  EXPECT_EQ(at(layer, 1.025, 2.525), PlanningGrid::kLethal);
}

TEST_F(ObstacleLayerTest, UsesTheSensorPoseAndBeamAngles) {
  ObstacleLayer layer;
  // Sensor facing +y; beam at -90 degrees from it points along +x.
  layer.add_scan(scan({0.5F}, static_cast<float>(-std::numbers::pi / 2)),
                 {sensor_.x, sensor_.y, std::numbers::pi / 2});
  update(layer);
  EXPECT_EQ(at(layer, 3.025, 2.525), PlanningGrid::kLethal);
}

TEST_F(ObstacleLayerTest, RefusesBadScansAndSkipsBadBeams) {
  ObstacleLayer layer;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(layer.add_scan(scan({1.0F}), {nan, 0.0, 0.0}));
  EXPECT_FALSE(layer.add_scan(scan({1.0F}, std::numeric_limits<float>::quiet_NaN()), sensor_));
  EXPECT_TRUE(layer.add_scan(scan({std::numeric_limits<float>::quiet_NaN(), 0.01F}), sensor_));
  EXPECT_TRUE(update(layer).empty());
  for (const auto cost : layer.observed().costs()) EXPECT_EQ(cost, PlanningGrid::kUnknown);
  ObstacleLayerOptions options;
  options.raytrace_range_m = -1.0;
  EXPECT_THROW(ObstacleLayer{options}, std::invalid_argument);
  options = {};
  options.obstacle_range_m = std::nan("");
  EXPECT_THROW(ObstacleLayer{options}, std::invalid_argument);
}

TEST_F(ObstacleLayerTest, ClearForgetsEverything) {
  ObstacleLayer layer;
  layer.add_scan(scan({1.0F}), sensor_);
  update(layer);
  layer.add_scan(scan({1.0F}), sensor_);
  layer.clear();
  EXPECT_EQ(update(layer), CellBounds::of_size(100, 100));
  for (const auto cost : layer.observed().costs()) EXPECT_EQ(cost, PlanningGrid::kUnknown);
}

TEST_F(ObstacleLayerTest, WritesIntoTheMasterByMax) {
  ObstacleLayer layer;
  layer.add_scan(scan({1.0F}), sensor_);
  CellBounds bounds = update(layer);
  master_.set_cost(*master_.cell_at({3.0, 2.525}), 100);  // another layer's cost under free cells
  layer.update(master_, bounds);
  EXPECT_EQ(master_.cost(*master_.cell_at({3.525, 2.525})), PlanningGrid::kLethal);
  EXPECT_EQ(master_.cost(*master_.cell_at({3.0, 2.525})), 100);
  EXPECT_EQ(layer.name(), "obstacle");
  EXPECT_EQ(layer.height_band(), (HeightBand{0.0, 2.0}));
}

}  // namespace
}  // namespace mobot::costmap
