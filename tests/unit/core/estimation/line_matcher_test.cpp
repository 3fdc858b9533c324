#include "core/estimation/line_matcher.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/unit/core/estimation/synthetic_world.h"

namespace mobot::estimation {
namespace {

using estimation_sim::rectangle_room;
using estimation_sim::Wall;
using estimation_sim::wall_lines;

// A map line as an exact observation from `pose`, in the base frame, with a given covariance.
perception::LineSegment observe(const perception::LineSegment& map_line,
                                const geometry::Pose2D& pose, double var_rho = 1e-4,
                                double var_alpha = 1e-4) {
  perception::LineSegment seen = perception::transform_line(geometry::inverse(pose), map_line);
  seen.var_rho_m2 = var_rho;
  seen.var_alpha_rad2 = var_alpha;
  seen.cov_rho_alpha_m_rad = 0.0;
  return seen;
}

const Eigen::Matrix3d kSmallCovariance = Eigen::Vector3d(1e-3, 1e-3, 1e-3).asDiagonal();

TEST(LineMatcher, EachWallFindsItsMapLine) {
  const auto map = wall_lines(rectangle_room(0.0, 0.0, 10.0, 8.0));
  const geometry::Pose2D pose{3.0, 2.0, 0.4};
  std::vector<perception::LineSegment> observed;
  for (int j : {2, 0, 3, 1}) observed.push_back(observe(map[j], pose));
  const auto matches = match_lines(pose, kSmallCovariance, observed, map);
  ASSERT_EQ(matches.size(), 4U);
  const int expected[] = {2, 0, 3, 1};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(matches[i].observed_index, i);
    EXPECT_EQ(matches[i].map_index, expected[i]);
    EXPECT_NEAR(matches[i].innovation.norm(), 0.0, 1e-9);
  }
}

TEST(LineMatcher, PicksTheNearerOfTwoParallelLines) {
  // Two faces of a wall 0.3 m apart, both facing the robot's side.
  const std::vector<Wall> walls = {{{0.0, 3.0}, {10.0, 3.0}}, {{0.0, 3.3}, {10.0, 3.3}}};
  const auto map = wall_lines(walls);
  const geometry::Pose2D truth{4.0, 1.0, 0.2};
  // The estimate is 0.1 m off toward the wall: the observation of the nearer face still lies
  // nearer (in Mahalanobis terms) to that face.
  const geometry::Pose2D estimate{4.0, 1.1, 0.2};
  const auto matches = match_lines(estimate, kSmallCovariance, {observe(map[0], truth)}, map);
  ASSERT_EQ(matches.size(), 1U);
  EXPECT_EQ(matches[0].map_index, 0);
  const auto far = match_lines(estimate, kSmallCovariance, {observe(map[1], truth)}, map);
  ASSERT_EQ(far.size(), 1U);
  EXPECT_EQ(far[0].map_index, 1);
}

TEST(LineMatcher, TheFarFaceOfAThinWallIsNeverMatched) {
  // The two faces of a 0.15 m wall; free space below the lower face and above the upper one.
  auto map = wall_lines({{{0.0, 3.0}, {10.0, 3.0}}, {{0.0, 3.15}, {10.0, 3.15}}});
  map[0].free_side = -1;  // toward the origin
  map[1].free_side = 1;
  const geometry::Pose2D truth{4.0, 1.0, 0.0};
  // An estimate 0.15 m too near the wall: the near face's observation now predicts the far face
  // exactly, but the robot is not on the far face's free side.
  const geometry::Pose2D estimate{4.0, 1.15, 0.0};
  // The rough pose of a manual initialisation (0.25 m, 0.1 rad), under which both faces pass the
  // gates.
  const Eigen::Matrix3d rough = Eigen::Vector3d(0.0625, 0.0625, 0.01).asDiagonal();
  const auto matches = match_lines(estimate, rough, {observe(map[0], truth)}, map);
  ASSERT_EQ(matches.size(), 1U);
  EXPECT_EQ(matches[0].map_index, 0);
  // Without the free side the far face wins.
  map[0].free_side = 0;
  map[1].free_side = 0;
  const auto unsided = match_lines(estimate, rough, {observe(map[0], truth)}, map);
  ASSERT_EQ(unsided.size(), 1U);
  EXPECT_EQ(unsided[0].map_index, 1);
}

TEST(LineMatcher, GatesRejectFarLines) {
  const auto map = wall_lines({{{0.0, 3.0}, {10.0, 3.0}}});
  const geometry::Pose2D pose{4.0, 1.0, 0.0};
  auto shifted = observe(map[0], pose);
  shifted.rho_m += 0.8;  // beyond gate_rho_m
  EXPECT_TRUE(match_lines(pose, kSmallCovariance, {shifted}, map).empty());

  auto turned = observe(map[0], pose);
  turned.alpha_rad += 0.5;  // beyond gate_alpha_rad
  EXPECT_TRUE(match_lines(pose, kSmallCovariance, {turned}, map).empty());

  // Inside the hard gates but 0.2 m off with a confident filter and observation: the
  // Mahalanobis gate rejects it...
  auto nudged = observe(map[0], pose, 1e-5, 1e-5);
  nudged.rho_m += 0.2;
  const Eigen::Matrix3d tight = Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal();
  EXPECT_TRUE(match_lines(pose, tight, {nudged}, map).empty());
  // ...while an uncertain filter accepts it.
  const Eigen::Matrix3d loose = Eigen::Vector3d(0.05, 0.05, 0.01).asDiagonal();
  EXPECT_EQ(match_lines(pose, loose, {nudged}, map).size(), 1U);
}

TEST(LineMatcher, EndpointCriterionTellsCollinearSegmentsApart) {
  // One wall line with a 3 m gap: two map segments with identical (rho, alpha).
  const auto map = wall_lines({{{0.0, 3.0}, {2.0, 3.0}}, {{5.0, 3.0}, {7.0, 3.0}}});
  const geometry::Pose2D pose{5.5, 1.0, 0.0};
  perception::LineSegment seen = observe(map[1], pose);
  // The robot sees x in [5.5, 6.5] of the wall (base frame: y = 2, x in [0, 1]).
  seen.start = {0.0, 2.0};
  seen.end = {1.0, 2.0};
  auto matches = match_lines(pose, kSmallCovariance, {seen}, map);
  ASSERT_EQ(matches.size(), 1U);
  EXPECT_EQ(matches[0].map_index, 1);

  // A segment in the gap (x in [3, 4]) matches neither map segment.
  seen.start = {-2.5, 2.0};
  seen.end = {-1.5, 2.0};
  EXPECT_TRUE(match_lines(pose, kSmallCovariance, {seen}, map).empty());

  // Without endpoints the criterion cannot apply: the line matches one of the two (a tie).
  seen.has_endpoints = false;
  EXPECT_EQ(match_lines(pose, kSmallCovariance, {seen}, map).size(), 1U);

  // Disabled by option.
  seen.has_endpoints = true;
  LineMatcherOptions no_endpoints;
  no_endpoints.endpoint_gate_m = 0.0;
  EXPECT_EQ(match_lines(pose, kSmallCovariance, {seen}, map, no_endpoints).size(), 1U);
}

TEST(LineMatcher, SkipsInvalidLines) {
  const auto map = wall_lines(rectangle_room(0.0, 0.0, 10.0, 8.0));
  const geometry::Pose2D pose{3.0, 2.0, 0.0};
  auto bad = observe(map[0], pose);
  bad.rho_m = std::nan("");
  auto broken_map = map;
  broken_map[1].alpha_rad = std::numeric_limits<double>::infinity();
  const auto matches = match_lines(pose, kSmallCovariance,
                                   {bad, observe(map[1], pose), observe(map[2], pose)}, broken_map);
  ASSERT_EQ(matches.size(), 1U);
  EXPECT_EQ(matches[0].observed_index, 2);
  EXPECT_EQ(matches[0].map_index, 2);
}

TEST(LineMatcher, NoiseIncludesTheMapTerms) {
  perception::LineSegment seen;
  seen.var_rho_m2 = 1e-3;
  seen.var_alpha_rad2 = 2e-3;
  seen.cov_rho_alpha_m_rad = 1e-4;
  const Eigen::Matrix2d r = line_measurement_noise(seen, {});
  EXPECT_NEAR(r(0, 0), 1.1e-3, 1e-15);
  EXPECT_NEAR(r(1, 1), 2.1e-3, 1e-15);
  EXPECT_NEAR(r(0, 1), 1e-4, 1e-15);
}

}  // namespace
}  // namespace mobot::estimation
