#include "core/estimation/particle_filter/pose_moments.h"

#include <gtest/gtest.h>

#include <limits>
#include <numbers>
#include <vector>

namespace mobot::estimation {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(PoseMoments, WeightedMeanAndCovariance) {
  const std::vector<WeightedPose> poses = {{{0.0, 0.0, 0.1}, 1.0}, {{2.0, 4.0, 0.3}, 3.0}};
  const PoseMoments m = weighted_pose_moments(poses);
  EXPECT_DOUBLE_EQ(m.weight, 4.0);
  EXPECT_DOUBLE_EQ(m.mean.x, 1.5);
  EXPECT_DOUBLE_EQ(m.mean.y, 3.0);
  // var = w1 w2 / W^2 * d^2 for two points.
  EXPECT_NEAR(m.covariance(0, 0), 3.0 / 16.0 * 4.0, 1e-12);
  EXPECT_NEAR(m.covariance(1, 1), 3.0 / 16.0 * 16.0, 1e-12);
  EXPECT_NEAR(m.covariance(0, 1), 3.0 / 16.0 * 8.0, 1e-12);
  EXPECT_NEAR(m.covariance(1, 0), m.covariance(0, 1), 1e-15);
  EXPECT_GT(m.covariance(2, 2), 0.0);
  EXPECT_GT(m.mean.theta, 0.2);  // the circular mean leans to the heavier heading
  EXPECT_LT(m.mean.theta, 0.3);
}

TEST(PoseMoments, HeadingsStraddlingPiHaveASmallSpreadAboutPi) {
  const std::vector<WeightedPose> poses = {{{0.0, 0.0, kPi - 0.1}, 1.0},
                                           {{0.0, 0.0, -kPi + 0.1}, 1.0}};
  const PoseMoments m = weighted_pose_moments(poses);
  EXPECT_NEAR(std::abs(m.mean.theta), kPi, 1e-12);
  EXPECT_NEAR(m.covariance(2, 2), 0.01, 1e-12);
}

TEST(PoseMoments, NoUsableWeightGivesZeroMoments) {
  EXPECT_EQ(weighted_pose_moments({}).weight, 0.0);
  const std::vector<WeightedPose> zero = {{{1.0, 2.0, 0.0}, 0.0}};
  const PoseMoments m = weighted_pose_moments(zero);
  EXPECT_EQ(m.mean, geometry::Pose2D{});
  EXPECT_TRUE(m.covariance.isZero());
  const std::vector<WeightedPose> nan = {
      {{1.0, 2.0, 0.0}, std::numeric_limits<double>::quiet_NaN()}};
  EXPECT_EQ(weighted_pose_moments(nan).weight, 0.0);
}

}  // namespace
}  // namespace mobot::estimation
