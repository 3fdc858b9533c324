#include "core/slam/carmen_log.h"

#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

namespace mobot::slam {
namespace {

std::string flaser(int beams, const std::string& tail = " 1.5 2.5 0.1 1.4 2.4 0.2 32.9 host 33.0") {
  std::string line = "FLASER " + std::to_string(beams);
  for (int i = 0; i < beams; ++i) line += i == 0 ? " 81.83" : " 1.25";
  return line + tail;
}

TEST(CarmenLog, ParsesA180BeamFlaserLine) {
  const CarmenLine line = parse_carmen_line(flaser(180));
  ASSERT_EQ(line.kind, CarmenLine::Kind::kLaser);
  const CarmenLaser& laser = *line.laser;
  ASSERT_EQ(laser.ranges_m.size(), 180U);
  EXPECT_FLOAT_EQ(laser.ranges_m[0], 81.83F);
  EXPECT_FLOAT_EQ(laser.ranges_m[1], 1.25F);
  EXPECT_EQ(laser.laser_pose, (geometry::Pose2D{1.5, 2.5, 0.1}));
  EXPECT_EQ(laser.odom_pose, (geometry::Pose2D{1.4, 2.4, 0.2}));
  EXPECT_DOUBLE_EQ(laser.timestamp_s, 32.9);
  // -90 .. +89 deg in 1 deg steps.
  EXPECT_NEAR(laser.angle_min_rad, -std::numbers::pi / 2.0, 1e-6);
  EXPECT_NEAR(laser.angle_min_rad + 179 * laser.angle_increment_rad,
              89.0 * std::numbers::pi / 180.0, 1e-5);
}

TEST(CarmenLog, OddBeamCountsReachBothEnds) {
  for (int beams : {181, 361}) {
    const CarmenLine line = parse_carmen_line(flaser(beams));
    ASSERT_EQ(line.kind, CarmenLine::Kind::kLaser) << beams;
    const CarmenLaser& laser = *line.laser;
    EXPECT_NEAR(laser.angle_min_rad + (beams - 1) * laser.angle_increment_rad,
                std::numbers::pi / 2.0, 1e-5);
  }
  EXPECT_NEAR(flaser_angle_increment_rad(360), std::numbers::pi / 360.0, 1e-12);
}

TEST(CarmenLog, ToleratesAMissingHostAndCarriageReturns) {
  EXPECT_EQ(parse_carmen_line(flaser(180, " 1 2 3 4 5 6 7.5")).kind, CarmenLine::Kind::kLaser);
  EXPECT_EQ(parse_carmen_line(flaser(180) + "\r").kind, CarmenLine::Kind::kLaser);
}

TEST(CarmenLog, SkipsCommentsBlankLinesAndOtherMessages) {
  EXPECT_EQ(parse_carmen_line("").kind, CarmenLine::Kind::kSkipped);
  EXPECT_EQ(parse_carmen_line("   ").kind, CarmenLine::Kind::kSkipped);
  EXPECT_EQ(parse_carmen_line("# message formats defined: PARAM SYNC ODOM").kind,
            CarmenLine::Kind::kSkipped);
  EXPECT_EQ(parse_carmen_line("ODOM 0 0 0 0 0 0 0.000246 pippo 0.000246").kind,
            CarmenLine::Kind::kSkipped);
  EXPECT_EQ(parse_carmen_line("PARAM robot_frontlaser_offset 0.0 nohost 0").kind,
            CarmenLine::Kind::kSkipped);
  EXPECT_EQ(parse_carmen_line("RLASER 2 1 1 0 0 0 0 0 0 1 h 1").kind, CarmenLine::Kind::kSkipped);
}

TEST(CarmenLog, ReportsMalformedLaserLines) {
  const CarmenLine::Kind bad = CarmenLine::Kind::kMalformed;
  EXPECT_EQ(parse_carmen_line("FLASER").kind, bad);
  EXPECT_EQ(parse_carmen_line("FLASER abc 1 2").kind, bad);
  EXPECT_EQ(parse_carmen_line("FLASER 0 1 2 3 4 5 6 7").kind, bad);
  EXPECT_EQ(parse_carmen_line("FLASER -3 1 2 3 4 5 6 7").kind, bad);
  EXPECT_EQ(parse_carmen_line("FLASER 2.5 1 2 3 4 5 6 7 8 9").kind, bad);
  EXPECT_EQ(parse_carmen_line("FLASER 99999999 1 2").kind, bad);
  EXPECT_EQ(parse_carmen_line(flaser(180, " 1 2 3")).kind, bad);              // truncated
  EXPECT_EQ(parse_carmen_line(flaser(180, " 1 2 x 4 5 6 7 h 8")).kind, bad);  // not a number
  EXPECT_EQ(parse_carmen_line(flaser(180, " 1 2 nan 4 5 6 7 h 8")).kind, bad);
  const CarmenLine line = parse_carmen_line(flaser(180, " 1 2 x 4 5 6 7 h 8"));
  EXPECT_NE(line.error.find("not a number"), std::string::npos);
  EXPECT_FALSE(line.laser.has_value());
}

TEST(CarmenLog, ParsesRobotLaser1) {
  // type start fov res max_range accuracy remission_mode n ranges m remissions laser pose robot
  // pose tv rv fwd side turn timestamp host logger_timestamp
  const std::string line =
      "ROBOTLASER1 0 -1.5708 3.14159 0.0174533 81.9 0.01 0 3 1.0 2.0 81.9 0 "
      "1.2 0.0 0.1 1.0 0.0 0.1 0.3 0.0 0.5 0.5 0.6 100.25 host 100.3";
  const CarmenLine parsed = parse_carmen_line(line);
  ASSERT_EQ(parsed.kind, CarmenLine::Kind::kLaser);
  EXPECT_EQ(parsed.laser->ranges_m.size(), 3U);
  EXPECT_FLOAT_EQ(parsed.laser->range_max_m, 81.9F);
  EXPECT_NEAR(parsed.laser->angle_increment_rad, 0.0174533, 1e-6);
  EXPECT_EQ(parsed.laser->laser_pose, (geometry::Pose2D{1.2, 0.0, 0.1}));
  EXPECT_EQ(parsed.laser->odom_pose, (geometry::Pose2D{1.0, 0.0, 0.1}));
  EXPECT_DOUBLE_EQ(parsed.laser->timestamp_s, 100.25);
  EXPECT_EQ(parse_carmen_line("ROBOTLASER1 0 -1.5 3.1 0.01 81 0.01 0 3 1.0").kind,
            CarmenLine::Kind::kMalformed);
}

TEST(CarmenLog, ToLaserScanMarksTheNoReturnRange) {
  const CarmenLaser laser = *parse_carmen_line(flaser(180)).laser;
  const msgs::LaserScan scan = to_laser_scan(laser, 50.0, {0.1, 0.0, 0.0});
  EXPECT_FLOAT_EQ(scan.range_max_m, 50.0F);
  EXPECT_EQ(scan.ranges_m.size(), 180U);
  EXPECT_DOUBLE_EQ(scan.sensor_in_base.x, 0.1);
  EXPECT_DOUBLE_EQ(scan.stamp_s, 32.9);
}

}  // namespace
}  // namespace mobot::slam
