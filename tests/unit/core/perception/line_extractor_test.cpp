#include "core/perception/line_extractor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "tests/unit/core/estimation/synthetic_world.h"

namespace mobot::perception {
namespace {

using estimation_sim::rectangle_room;
using estimation_sim::ScanSpec;
using estimation_sim::simulate_scan;
using estimation_sim::Wall;

constexpr double kPi = std::numbers::pi;

// Index of the extracted line closest to (rho, alpha), or -1.
int find_line(const std::vector<LineSegment>& lines, double rho, double alpha,
              double rho_tol = 0.05, double alpha_tol = 0.03) {
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (std::abs(lines[i].rho_m - rho) < rho_tol &&
        std::abs(geometry::wrap_angle(lines[i].alpha_rad - alpha)) < alpha_tol) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

std::string describe(const std::vector<LineSegment>& lines) {
  std::string out;
  for (const auto& l : lines) {
    out += "(rho " + std::to_string(l.rho_m) + ", alpha " + std::to_string(l.alpha_rad) + ", n " +
           std::to_string(l.point_count) + ", len " + std::to_string(l.length_m()) + ") ";
  }
  return out;
}

const std::vector<Wall> kCorridor = {{{-20.0, 1.5}, {20.0, 1.5}}, {{-20.0, -1.0}, {20.0, -1.0}}};

TEST(LineExtractor, CorridorGivesTwoParallelLines) {
  const auto scan = simulate_scan(kCorridor, {}, {}, ScanSpec{});
  const auto lines = LineExtractor().extract(scan);
  ASSERT_EQ(lines.size(), 2U) << describe(lines);
  const int left = find_line(lines, 1.5, kPi / 2, 1e-6, 1e-6);
  const int right = find_line(lines, 1.0, -kPi / 2, 1e-6, 1e-6);
  ASSERT_GE(left, 0) << describe(lines);
  ASSERT_GE(right, 0) << describe(lines);
  // Endpoints lie on the walls, and each wall is seen over several metres.
  EXPECT_NEAR(lines[left].start.y, 1.5, 1e-6);
  EXPECT_NEAR(lines[left].end.y, 1.5, 1e-6);
  EXPECT_GT(lines[left].length_m(), 5.0);
  EXPECT_GT(lines[right].length_m(), 5.0);
  EXPECT_GT(lines[left].var_rho_m2, 0.0);
  EXPECT_GT(lines[left].var_alpha_rad2, 0.0);
}

TEST(LineExtractor, CornerGivesTwoLinesMeetingAtTheCorner) {
  const std::vector<Wall> corner = {{{3.0, -5.0}, {3.0, 2.0}}, {{3.0, 2.0}, {-5.0, 2.0}}};
  const auto scan = simulate_scan(corner, {}, {}, ScanSpec{});
  const auto lines = LineExtractor().extract(scan);
  ASSERT_EQ(lines.size(), 2U) << describe(lines);
  const int front = find_line(lines, 3.0, 0.0, 1e-6, 1e-6);
  const int side = find_line(lines, 2.0, kPi / 2, 1e-6, 1e-6);
  ASSERT_GE(front, 0) << describe(lines);
  ASSERT_GE(side, 0) << describe(lines);
  // The scan runs right to left: the front wall ends and the side wall starts at the corner.
  EXPECT_NEAR(lines[front].end.x, 3.0, 1e-6);
  EXPECT_NEAR(lines[front].end.y, 2.0, 0.05);
  EXPECT_NEAR(lines[side].start.x, 3.0, 0.05);
}

TEST(LineExtractor, NoisyCorridorStaysWithinClaimedCovariance) {
  std::mt19937 rng(3);
  ScanSpec spec;
  spec.range_sigma_m = 0.01;
  int checked = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const auto scan = simulate_scan(kCorridor, {}, {}, spec, &rng);
    const auto lines = LineExtractor().extract(scan);
    ASSERT_EQ(lines.size(), 2U) << describe(lines);
    for (const auto& line : lines) {
      const double rho = line.alpha_rad > 0 ? 1.5 : 1.0;
      const double alpha = line.alpha_rad > 0 ? kPi / 2 : -kPi / 2;
      const double rho_error = line.rho_m - rho;
      const double alpha_error = geometry::wrap_angle(line.alpha_rad - alpha);
      EXPECT_LT(std::abs(rho_error), 0.01);
      EXPECT_LT(std::abs(alpha_error), 0.005);
      EXPECT_LT(std::abs(rho_error) / std::sqrt(line.var_rho_m2), 4.0);
      EXPECT_LT(std::abs(alpha_error) / std::sqrt(line.var_alpha_rad2), 4.0);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 40);
}

TEST(LineExtractor, SmallGapIsBridgedAndLargeGapSplits) {
  const std::vector<Wall> wall = {{{3.0, -6.0}, {3.0, 6.0}}};
  auto scan = simulate_scan(wall, {}, {}, ScanSpec{});
  // Three missing beams near the middle (about 8 cm of wall).
  for (int i = 178; i < 181; ++i) scan.ranges_m[i] = std::numeric_limits<float>::quiet_NaN();
  auto lines = LineExtractor().extract(scan);
  ASSERT_EQ(lines.size(), 1U) << describe(lines);
  EXPECT_GE(find_line(lines, 3.0, 0.0, 1e-6, 1e-6), 0);

  // Forty missing beams (about 1 m): two segments of the same wall.
  for (int i = 160; i < 200; ++i) scan.ranges_m[i] = std::numeric_limits<float>::infinity();
  lines = LineExtractor().extract(scan);
  ASSERT_EQ(lines.size(), 2U) << describe(lines);
  for (const auto& line : lines) {
    EXPECT_NEAR(line.rho_m, 3.0, 1e-6);
    EXPECT_NEAR(line.alpha_rad, 0.0, 1e-6);
  }
}

TEST(LineExtractor, OutlierClusterMakesNoLine) {
  const std::vector<Wall> wall = {{{3.0, -6.0}, {3.0, 6.0}}};
  std::mt19937 rng(5);
  ScanSpec spec;
  spec.range_sigma_m = 0.01;
  auto scan = simulate_scan(wall, {}, {}, spec, &rng);
  // A burst of spurious short returns (dust, a passing leg) in front of the wall.
  std::uniform_real_distribution<float> spurious(0.5F, 2.0F);
  for (int i = 150; i < 158; ++i) scan.ranges_m[i] = spurious(rng);
  // and a lone spike inside the wall's run
  scan.ranges_m[220] = 1.0F;
  const auto lines = LineExtractor().extract(scan);
  ASSERT_GE(lines.size(), 1U);
  for (const auto& line : lines) {
    EXPECT_NEAR(line.rho_m, 3.0, 0.02) << describe(lines);
    EXPECT_NEAR(line.alpha_rad, 0.0, 0.01) << describe(lines);
  }
}

TEST(LineExtractor, SmallObjectInFrontOfWallIsIgnored) {
  std::vector<Wall> scene = {{{3.0, -6.0}, {3.0, 6.0}}};
  // A 10 cm box 1 m in front of the wall: too short to be a line, its shadow is bridged.
  const auto box = rectangle_room(1.9, 0.4, 2.0, 0.5);
  scene.insert(scene.end(), box.begin(), box.end());
  const auto lines = LineExtractor().extract(simulate_scan(scene, {}, {}, ScanSpec{}));
  ASSERT_EQ(lines.size(), 1U) << describe(lines);
  EXPECT_NEAR(lines[0].rho_m, 3.0, 1e-6);
}

TEST(LineExtractor, FullCircleScanJoinsTheWallBehind) {
  ScanSpec spec;
  spec.beams = 720;
  spec.fov_rad = 2 * kPi;
  // The wall at x = -2 crosses the scan's start angle (-pi).
  const auto scan = simulate_scan(rectangle_room(-2.0, -3.0, 4.0, 2.5), {}, {}, spec);
  const auto lines = LineExtractor().extract(scan);
  ASSERT_EQ(lines.size(), 4U) << describe(lines);
  // A return within the threshold of a corner may join the neighbouring wall: millimetre effects.
  EXPECT_GE(find_line(lines, 2.0, kPi, 1e-3, 1e-3), 0) << describe(lines);
  EXPECT_GE(find_line(lines, 4.0, 0.0, 1e-3, 1e-3), 0);
  EXPECT_GE(find_line(lines, 3.0, -kPi / 2, 1e-3, 1e-3), 0);
  EXPECT_GE(find_line(lines, 2.5, kPi / 2, 1e-3, 1e-3), 0);
}

TEST(LineExtractor, MountingDoesNotMatterInSensorFrame) {
  // Lines come out in the sensor frame whatever the scan says about the mounting.
  const geometry::Pose2D mount{0.2, 0.1, 0.3};
  const auto scan = simulate_scan(kCorridor, geometry::inverse(mount), mount, ScanSpec{});
  const auto lines = LineExtractor().extract(scan);
  EXPECT_EQ(lines.size(), 2U) << describe(lines);
  EXPECT_GE(find_line(lines, 1.5, kPi / 2, 1e-6, 1e-6), 0) << describe(lines);
}

TEST(LineExtractor, EmptyAndBrokenScansGiveNothing) {
  const LineExtractor extractor;
  msgs::LaserScan empty;
  EXPECT_TRUE(extractor.extract(empty).empty());

  auto scan = simulate_scan(kCorridor, {}, {}, ScanSpec{});
  auto no_returns = scan;
  for (auto& r : no_returns.ranges_m) r = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(extractor.extract(no_returns).empty());

  auto all_nan = scan;
  for (auto& r : all_nan.ranges_m) r = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(extractor.extract(all_nan).empty());

  auto zero_increment = scan;
  zero_increment.angle_increment_rad = 0.0F;
  EXPECT_TRUE(extractor.extract(zero_increment).empty());

  auto nan_angle = scan;
  nan_angle.angle_min_rad = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(extractor.extract(nan_angle).empty());

  // Fewer points than a segment needs.
  msgs::LaserScan few = scan;
  few.ranges_m.resize(4);
  EXPECT_TRUE(extractor.extract(few).empty());
}

TEST(LineExtractor, DegenerateScanOfOnePointGivesNothing) {
  // All returns crowd into a few millimetres: no segment is long enough to be a wall.
  msgs::LaserScan scan;
  scan.angle_min_rad = -1.5F;
  scan.angle_increment_rad = 1e-5F;
  scan.range_min_m = 0.1F;
  scan.range_max_m = 30.0F;
  scan.ranges_m.assign(361, 0.5F);
  EXPECT_TRUE(LineExtractor().extract(scan).empty());
}

TEST(LineExtractor, ClockwiseScanFindsTheSameLines) {
  auto scan = simulate_scan(kCorridor, {}, {}, ScanSpec{});
  auto reversed = scan;
  reversed.angle_min_rad = -scan.angle_min_rad;
  reversed.angle_increment_rad = -scan.angle_increment_rad;
  std::reverse(reversed.ranges_m.begin(), reversed.ranges_m.end());
  const auto lines = LineExtractor().extract(reversed);
  ASSERT_EQ(lines.size(), 2U) << describe(lines);
  EXPECT_GE(find_line(lines, 1.5, kPi / 2, 1e-6, 1e-6), 0);
}

}  // namespace
}  // namespace mobot::perception
