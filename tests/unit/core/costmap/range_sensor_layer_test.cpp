#include "core/costmap/range_sensor_layer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace mobot::costmap {
namespace {

using planning::PlanningGrid;

msgs::RangeReading reading(double range_m, double cone_rad = 0.5, double range_max_m = 3.0,
                           geometry::Pose2D mount = {}) {
  msgs::RangeReading out;
  out.sensor_in_base = mount;
  out.cone_rad = cone_rad;
  out.range_min_m = 0.02;
  out.range_max_m = range_max_m;
  out.range_m = range_m;
  return out;
}

class RangeSensorLayerTest : public ::testing::Test {
 protected:
  RangeSensorLayerTest() : master_(100, 100, 0.05, {}) {}
  CellBounds update(RangeSensorLayer& layer) {
    CellBounds bounds;
    layer.update_bounds(master_, bounds);
    return bounds;
  }
  std::uint8_t at(const RangeSensorLayer& layer, double x, double y) {
    return layer.observed().cost(*master_.cell_at({x, y}));
  }
  // Polar point around the base (at the grid's centre, facing +x).
  std::uint8_t polar(const RangeSensorLayer& layer, double r, double bearing) {
    return at(layer, base_.x + r * std::cos(bearing), base_.y + r * std::sin(bearing));
  }
  PlanningGrid master_;
  const geometry::Pose2D base_{2.5, 2.5, 0.0};
};

TEST_F(RangeSensorLayerTest, MarksTheArcAtTheEchoAndClearsTheConeBeforeIt) {
  RangeSensorLayer layer;
  const std::vector<msgs::RangeReading> ring{reading(1.0)};
  ASSERT_TRUE(layer.add_readings(ring, base_));
  update(layer);
  // The arc: on the axis and near both edges of the 0.5 rad cone.
  for (const double bearing : {0.0, 0.2, -0.2}) {
    EXPECT_EQ(polar(layer, 1.0, bearing), PlanningGrid::kLethal) << bearing;
    EXPECT_EQ(polar(layer, 0.6, bearing), PlanningGrid::kFree) << bearing;
    EXPECT_EQ(polar(layer, 1.3, bearing), PlanningGrid::kUnknown) << bearing;
  }
  // Outside the cone: untouched.
  EXPECT_EQ(polar(layer, 0.6, 0.45), PlanningGrid::kUnknown);
  EXPECT_EQ(polar(layer, 1.0, -0.45), PlanningGrid::kUnknown);
}

TEST_F(RangeSensorLayerTest, AReadingAtRangeMaxMarksNothingAndClearsTheCone) {
  RangeSensorLayer layer;
  layer.add_readings(std::vector{reading(1.0)}, base_);
  update(layer);
  layer.add_readings(std::vector{reading(3.0)}, base_);  // the obstacle left
  update(layer);
  EXPECT_EQ(polar(layer, 1.0, 0.0), PlanningGrid::kFree);
  EXPECT_EQ(polar(layer, 2.0, 0.1), PlanningGrid::kFree);
  int lethal = 0;
  for (const auto cost : layer.observed().costs()) lethal += cost == PlanningGrid::kLethal;
  EXPECT_EQ(lethal, 0);

  RangeSensorLayerOptions options;
  options.clear_on_max_reading = false;
  RangeSensorLayer keeps(options);
  keeps.add_readings(std::vector{reading(1.0)}, base_);
  update(keeps);
  keeps.add_readings(std::vector{reading(3.0)}, base_);
  update(keeps);
  EXPECT_EQ(polar(keeps, 1.0, 0.0), PlanningGrid::kLethal);
}

TEST_F(RangeSensorLayerTest, ANarrowInfraredConeStillMarksAndClearsItsAxis) {
  RangeSensorLayerOptions options;
  options.name = "ir";
  RangeSensorLayer layer(options);
  // A Sharp IR: 0.02 rad, 0.8 m max, mounted 0.2 m ahead of the base facing left.
  layer.add_readings(std::vector{reading(0.3, 0.02, 0.8, {0.2, 0.0, std::numbers::pi / 2})}, base_);
  update(layer);
  EXPECT_EQ(layer.name(), "ir");
  EXPECT_EQ(at(layer, 2.7, 2.8), PlanningGrid::kLethal);
  EXPECT_EQ(at(layer, 2.7, 2.6), PlanningGrid::kFree);
}

TEST_F(RangeSensorLayerTest, ReadingsBeyondTheMarkRangeOnlyClear) {
  RangeSensorLayerOptions options;
  options.max_mark_range_m = 0.8;
  RangeSensorLayer layer(options);
  layer.add_readings(std::vector{reading(1.0)}, base_);
  update(layer);
  EXPECT_EQ(polar(layer, 1.0, 0.0), PlanningGrid::kUnknown);
  EXPECT_EQ(polar(layer, 0.6, 0.0), PlanningGrid::kFree);
}

TEST_F(RangeSensorLayerTest, SkipsBadReadingsAndRefusesABadPose) {
  RangeSensorLayer layer;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(layer.add_readings(std::vector{reading(1.0)}, {nan, 0.0, 0.0}));
  const std::vector<msgs::RangeReading> bad{
      reading(nan),           reading(0.01),
      reading(1.0, 0.0),      reading(1.0, std::numbers::pi),
      reading(1.0, 0.5, 0.0), reading(1.0, 0.5, 3.0, {nan, 0.0, 0.0})};
  EXPECT_TRUE(layer.add_readings(bad, base_));
  EXPECT_TRUE(update(layer).empty());
  RangeSensorLayerOptions options;
  options.arc_thickness_m = -0.1;
  EXPECT_THROW(RangeSensorLayer{options}, std::invalid_argument);
  options = {};
  options.max_mark_range_m = std::nan("");
  EXPECT_THROW(RangeSensorLayer{options}, std::invalid_argument);
}

TEST_F(RangeSensorLayerTest, ReportsTheCellsItChanged) {
  RangeSensorLayer layer;
  layer.add_readings(std::vector{reading(1.0)}, base_);
  const CellBounds bounds = update(layer);
  EXPECT_TRUE(bounds.contains(*master_.cell_at({base_.x, base_.y})));
  EXPECT_TRUE(bounds.contains(*master_.cell_at({base_.x + 1.0, base_.y})));
  EXPECT_LE(bounds.max_x, 72);
  EXPECT_GE(bounds.min_y, 39);
  EXPECT_LE(bounds.max_y, 61);
}

}  // namespace
}  // namespace mobot::costmap
