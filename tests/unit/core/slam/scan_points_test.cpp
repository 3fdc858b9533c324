#include "core/slam/scan_points.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <gtest/gtest.h>

namespace mobot::slam {
namespace {

msgs::LaserScan three_beams(float a, float b, float c) {
  msgs::LaserScan scan;
  scan.angle_min_rad = static_cast<float>(-std::numbers::pi / 2.0);
  scan.angle_increment_rad = static_cast<float>(std::numbers::pi / 2.0);
  scan.range_min_m = 0.1F;
  scan.range_max_m = 20.0F;
  scan.ranges_m = {a, b, c};
  return scan;
}

TEST(ScanPoints, ConvertsBeamsToBaseFramePoints) {
  const ScanPoints points = scan_to_points(three_beams(1.0F, 2.0F, 3.0F));
  ASSERT_EQ(points.points_in_base.size(), 3U);
  EXPECT_NEAR(points.points_in_base[0].x, 0.0, 1e-6);
  EXPECT_NEAR(points.points_in_base[0].y, -1.0, 1e-6);
  EXPECT_NEAR(points.points_in_base[1].x, 2.0, 1e-6);
  EXPECT_NEAR(points.points_in_base[2].y, 3.0, 1e-6);
  EXPECT_TRUE(points.misses_in_base.empty());
}

TEST(ScanPoints, HonoursTheSensorMounting) {
  msgs::LaserScan scan = three_beams(1.0F, 1.0F, 1.0F);
  scan.sensor_in_base = {0.2, 0.1, std::numbers::pi};  // mounted backwards
  const ScanPoints points = scan_to_points(scan);
  EXPECT_DOUBLE_EQ(points.sensor_origin_in_base.x, 0.2);
  ASSERT_EQ(points.points_in_base.size(), 3U);
  EXPECT_NEAR(points.points_in_base[1].x, 0.2 - 1.0, 1e-6);  // straight ahead of the sensor
  EXPECT_NEAR(points.points_in_base[1].y, 0.1, 1e-6);
}

TEST(ScanPoints, SkipsBeamsOutsideTheUsableRange) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  // Too close and NaN: nothing. Beyond 8 m, at range_max and +inf: free space up to 8 m.
  EXPECT_TRUE(scan_to_points(three_beams(0.01F, nan, 0.05F)).points_in_base.empty());
  EXPECT_TRUE(scan_to_points(three_beams(0.01F, nan, 0.05F)).misses_in_base.empty());
  const ScanPoints far = scan_to_points(three_beams(9.0F, 20.0F, inf));
  EXPECT_TRUE(far.points_in_base.empty());
  ASSERT_EQ(far.misses_in_base.size(), 3U);
  EXPECT_NEAR(std::hypot(far.misses_in_base[1].x, far.misses_in_base[1].y), 8.0, 1e-9);
  ScanPointsOptions longer;
  longer.max_range_m = 10.0;
  EXPECT_EQ(scan_to_points(three_beams(9.0F, 20.0F, inf), longer).points_in_base.size(), 1U);
}

TEST(ScanPoints, EmptyAndNonFiniteScansGiveNoPoints) {
  msgs::LaserScan empty;
  EXPECT_TRUE(scan_to_points(empty).points_in_base.empty());
  msgs::LaserScan bad = three_beams(1.0F, 1.0F, 1.0F);
  bad.angle_increment_rad = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(scan_to_points(bad).points_in_base.empty());
  bad = three_beams(1.0F, 1.0F, 1.0F);
  bad.sensor_in_base.x = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(scan_to_points(bad).points_in_base.empty());
}

TEST(ScanPoints, RejectsBadOptions) {
  const msgs::LaserScan scan = three_beams(1.0F, 1.0F, 1.0F);
  EXPECT_THROW(scan_to_points(scan, {0.0, 0.05, 0.0}), std::invalid_argument);
  EXPECT_THROW(scan_to_points(scan, {8.0, -1.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(scan_to_points(scan, {8.0, 9.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(scan_to_points(scan, {8.0, 0.05, -0.1}), std::invalid_argument);
  EXPECT_THROW(scan_to_points(scan, {std::nan(""), 0.05, 0.0}), std::invalid_argument);
}

TEST(VoxelFilter, KeepsOneCentroidPerVoxelInScanOrder) {
  const std::vector<geometry::Point2D> points = {{0.01, 0.01}, {1.0, 1.0}, {0.03, 0.03}};
  const auto filtered = voxel_filter(points, 0.05);
  ASSERT_EQ(filtered.size(), 2U);
  EXPECT_NEAR(filtered[0].x, 0.02, 1e-12);
  EXPECT_NEAR(filtered[1].x, 1.0, 1e-12);
  EXPECT_EQ(voxel_filter(points, 0.0).size(), 3U);
  EXPECT_TRUE(voxel_filter({}, 0.05).empty());
}

}  // namespace
}  // namespace mobot::slam
