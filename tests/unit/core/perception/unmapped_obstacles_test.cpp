#include "core/perception/unmapped_obstacles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace mobot::perception {
namespace {

// A 4 x 4 m free room with a lethal wall along x = 3.9 .. 4.0.
std::shared_ptr<const planning::PlanningGrid> room() {
  auto grid = std::make_shared<planning::PlanningGrid>(80, 80, 0.05, geometry::Pose2D{});
  for (int y = 0; y < 80; ++y) {
    for (int x = 78; x < 80; ++x) grid->set_cost({x, y}, planning::PlanningGrid::kLethal);
  }
  return grid;
}

msgs::RangeReading ir(double range_m, double angle_rad = 0.0) {
  msgs::RangeReading reading;
  reading.sensor_in_base = {0.0, 0.0, angle_rad};
  reading.cone_rad = 0.1;
  reading.range_min_m = 0.1;
  reading.range_max_m = 0.8;
  reading.range_m = range_m;
  return reading;
}

TEST(UnmappedObstacles, ShortRangeEchoesAreHeldThenForgotten) {
  UnmappedObstaclesOptions options;
  options.range_echo_hold_s = 2.0;
  UnmappedObstacles obstacles(options);
  obstacles.set_map(room());
  const std::vector<msgs::RangeReading> ring{ir(0.5), ir(0.8, 1.0)};  // an echo, a max reading
  obstacles.observe_ranges(ring, {1.0, 2.0, 0.0}, 9.95);
  obstacles.observe_ranges(ring, {1.0, 2.0, 0.0}, 10.0);
  ASSERT_EQ(obstacles.points().size(), 1U);
  EXPECT_NEAR(obstacles.points()[0].x, 1.5, 1e-9);
  EXPECT_NEAR(obstacles.points()[0].y, 2.0, 1e-9);
  EXPECT_TRUE(obstacles.blocks({{0.5, 2.0}, {3.0, 2.0}}, 0.2));
  // Turned away: nothing echoes now, the table is still there for the planner...
  obstacles.observe_ranges(std::vector<msgs::RangeReading>{ir(0.8)}, {1.0, 2.0, 3.0}, 11.5);
  EXPECT_EQ(obstacles.points().size(), 1U);
  // ... until the hold time has passed.
  obstacles.observe_ranges(std::vector<msgs::RangeReading>{ir(0.8)}, {1.0, 2.0, 3.0}, 12.5);
  EXPECT_TRUE(obstacles.points().empty());
}

// One sensor's lone near reading between two "nothing" readings is a spike; the same echo twice
// in a row is an obstacle; a reading that jumps by more than the agreement starts over.
TEST(UnmappedObstacles, ALoneRangeSpikeIsNotAnObstacle) {
  UnmappedObstacles obstacles;
  obstacles.set_map(room());
  const auto observe = [&](double range_m, double now_s) {
    obstacles.observe_ranges(std::vector<msgs::RangeReading>{ir(0.8), ir(range_m, 1.5)},
                             {1.0, 2.0, 0.0}, now_s);
  };
  observe(0.8, 1.00);
  observe(0.6, 1.05);  // spike
  observe(0.8, 1.10);
  observe(0.6, 1.15);  // another, not in a row with the first
  EXPECT_TRUE(obstacles.points().empty());
  observe(0.35, 1.20);  // 0.25 m from the last: not the same echo
  EXPECT_TRUE(obstacles.points().empty());
  observe(0.37, 1.25);  // the same echo again: confirmed
  ASSERT_EQ(obstacles.points().size(), 1U);
  EXPECT_NEAR(std::hypot(obstacles.points()[0].x - 1.0, obstacles.points()[0].y - 2.0), 0.37, 1e-9);
}

TEST(UnmappedObstacles, EchoesOfMappedWallsAndBadReadingsAreNotObstacles) {
  UnmappedObstacles obstacles;
  obstacles.set_map(room());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<msgs::RangeReading> ring{ir(0.45), ir(nan), ir(0.05), ir(-1.0)};
  obstacles.observe_ranges(ring, {3.5, 2.0, 0.0}, 1.0);  // 0.45 m ahead: the wall at x 3.95
  EXPECT_TRUE(obstacles.points().empty());
}

TEST(UnmappedObstacles, AScanReplacesOnlyTheLaserPoints) {
  UnmappedObstacles obstacles;
  obstacles.set_map(room());
  obstacles.observe_ranges(std::vector<msgs::RangeReading>{ir(0.5)}, {1.0, 1.0, 0.0}, 0.95);
  obstacles.observe_ranges(std::vector<msgs::RangeReading>{ir(0.5)}, {1.0, 1.0, 0.0}, 1.0);
  msgs::LaserScan scan;
  scan.angle_min_rad = 0.0F;
  scan.angle_increment_rad = 0.1F;
  scan.range_min_m = 0.1F;
  scan.range_max_m = 10.0F;
  scan.ranges_m = {1.0F, 20.0F};
  obstacles.observe_scan(scan, {1.0, 3.0, 0.0});
  EXPECT_EQ(obstacles.points().size(), 2U);
  scan.ranges_m = {20.0F, 20.0F};
  obstacles.observe_scan(scan, {1.0, 3.0, 0.0});
  ASSERT_EQ(obstacles.points().size(), 1U);
  EXPECT_NEAR(obstacles.points()[0].x, 1.5, 1e-9);
}

}  // namespace
}  // namespace mobot::perception
