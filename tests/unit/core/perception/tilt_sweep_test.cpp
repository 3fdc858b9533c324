// P1 geometry and the R1 sweep schedule against hand-computed values.
#include "core/perception/tilt_sweep.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace mobot::perception {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(SweepMode, Table21) {
  ASSERT_TRUE(find_sweep_mode(10.0, 1.0));
  EXPECT_EQ(find_sweep_mode(10.0, 1.0)->scans, 81);
  EXPECT_EQ(find_sweep_mode(10.0, 0.5)->scans, 40);
  EXPECT_EQ(find_sweep_mode(10.0, 0.25)->scans, 24);
  EXPECT_EQ(find_sweep_mode(42.0, 1.0)->scans, 320);
  EXPECT_EQ(find_sweep_mode(42.0, 0.5)->scans, 160);
  EXPECT_EQ(find_sweep_mode(42.0, 0.25)->scans, 100);
  EXPECT_FALSE(find_sweep_mode(20.0, 1.0));
  EXPECT_FALSE(find_sweep_mode(10.0, 2.0));
  EXPECT_EQ(sweep_modes().size(), 6U);
}

TEST(SweepMode, PitchComesFromTheScanCount) {
  // delta_alpha = 25 deg / n_s, starting at -5 deg at the limit switch.
  EXPECT_NEAR(assigned_pitch_rad(0, 81), -5.0 * kDeg, 1e-12);
  EXPECT_NEAR(assigned_pitch_rad(1, 100), -4.75 * kDeg, 1e-12);
  EXPECT_NEAR(assigned_pitch_rad(40, 40), 20.0 * kDeg, 1e-12);
  EXPECT_NEAR(assigned_pitch_rad(20, 100), 0.0, 1e-12);
}

TEST(BeamPoint, P1Equation) {
  // Straight ahead, level: y forward, at the mounting height.
  const SensorPoint ahead = beam_point(2.0, 0.0, 90.0 * kDeg, 0.4);
  EXPECT_NEAR(ahead.x_m, 0.0, 1e-12);
  EXPECT_NEAR(ahead.y_m, 2.0, 1e-12);
  EXPECT_NEAR(ahead.z_m, 0.4, 1e-12);
  // The source's flat target at 2 850 mm, beam 45 deg, pitch 10 deg: by hand,
  // x = y = 2.85 * 0.98480775 * 0.70710678 = 1.984638..., z = 2.85 * 0.17364818 + 0.4 = 0.89490...
  const SensorPoint p = beam_point(2.85, 10.0 * kDeg, 45.0 * kDeg, 0.4);
  EXPECT_NEAR(p.x_m, 1.984638, 1e-6);
  EXPECT_NEAR(p.y_m, 1.984638, 1e-6);
  EXPECT_NEAR(p.z_m, 0.894897, 1e-6);
  // At -5 deg the beam meets the floor 4.58 m ahead (R1).
  const double floor_range_m = 0.4 / std::sin(5.0 * kDeg);
  const SensorPoint floor = beam_point(floor_range_m, -5.0 * kDeg, 90.0 * kDeg, 0.4);
  EXPECT_NEAR(floor.z_m, 0.0, 1e-12);
  EXPECT_NEAR(floor.y_m, 4.572, 1e-3);
}

TEST(AppendScan, PutsPointsInTheMapFrame) {
  msgs::TiltScan scan;
  scan.pitch_rad = 0.0;
  scan.bearing_min_rad = 0.0;
  scan.bearing_step_rad = 45.0 * kDeg;
  scan.range_min_m = 0.4F;
  scan.range_max_m = 80.0F;
  scan.sensor_in_base = {0.2, 0.0, 0.0};
  scan.sensor_height_m = 0.4;
  // Bearings 0 (right), 45, 90 (ahead), 135, 180 (left); the 45 and 135 deg beams have no return.
  scan.ranges_m = {1.0F, 0.1F, 3.0F, 81.0F, 2.0F};
  scan.intensities = {0.1F, 0.2F, 0.3F, 0.4F, 0.5F};
  PointCloud cloud;
  append_scan(scan, {1.0, 2.0, std::numbers::pi / 2.0}, cloud);  // facing +y
  ASSERT_EQ(cloud.size(), 3U);
  // The sensor sits at (1, 2.2). Right of a robot facing +y is +x.
  EXPECT_NEAR(cloud[0].x_m, 2.0, 1e-6);
  EXPECT_NEAR(cloud[0].y_m, 2.2, 1e-6);
  EXPECT_NEAR(cloud[1].x_m, 1.0, 1e-6);
  EXPECT_NEAR(cloud[1].y_m, 5.2, 1e-6);
  EXPECT_NEAR(cloud[2].x_m, -1.0, 1e-6);
  EXPECT_NEAR(cloud[2].y_m, 2.2, 1e-6);
  for (const auto& point : cloud) EXPECT_NEAR(point.z_m, 0.4, 1e-6);
  EXPECT_FLOAT_EQ(cloud[1].intensity, 0.3F);
}

TEST(AppendScan, PitchRaisesThePoint) {
  msgs::TiltScan scan;
  scan.pitch_rad = 10.0 * kDeg;
  scan.bearing_min_rad = 90.0 * kDeg;
  scan.bearing_step_rad = 1.0 * kDeg;
  scan.range_min_m = 0.4F;
  scan.range_max_m = 80.0F;
  scan.sensor_height_m = 0.4;
  scan.ranges_m = {2.85F};
  PointCloud cloud;
  append_scan(scan, {0.0, 0.0, 0.0}, cloud);
  ASSERT_EQ(cloud.size(), 1U);
  EXPECT_NEAR(cloud[0].x_m, 2.85 * std::cos(10.0 * kDeg), 1e-5);
  EXPECT_NEAR(cloud[0].y_m, 0.0, 1e-6);
  EXPECT_NEAR(cloud[0].z_m, 0.894897, 1e-5);
}

}  // namespace
}  // namespace mobot::perception
