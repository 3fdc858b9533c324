#include "core/estimation/particle_filter/particle_clusters.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>
#include <vector>

namespace mobot::estimation {
namespace {

constexpr double kPi = std::numbers::pi;

void add_blob(std::vector<WeightedPose>& out, geometry::Pose2D centre, int count, double weight,
              std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 0.1);
  for (int i = 0; i < count; ++i) {
    out.push_back(
        {{centre.x + n(rng), centre.y + n(rng), geometry::wrap_angle(centre.theta + 0.5 * n(rng))},
         weight});
  }
}

TEST(ParticleClusters, SeparatesHypothesesAndSortsThemByWeight) {
  std::mt19937_64 rng(2);
  std::vector<WeightedPose> particles;
  add_blob(particles, {1.0, 1.0, 0.5}, 300, 1.0, rng);
  add_blob(particles, {6.0, 2.0, -1.0}, 200, 2.0, rng);  // fewer but heavier
  const auto clusters = cluster_particles(particles, {});
  ASSERT_EQ(clusters.size(), 2U);
  EXPECT_EQ(clusters[0].count, 200U);
  EXPECT_DOUBLE_EQ(clusters[0].moments.weight, 400.0);
  EXPECT_NEAR(clusters[0].moments.mean.x, 6.0, 0.03);
  EXPECT_NEAR(clusters[0].moments.mean.theta, -1.0, 0.03);
  EXPECT_EQ(clusters[1].count, 300U);
  EXPECT_NEAR(clusters[1].moments.mean.y, 1.0, 0.03);
  EXPECT_NEAR(clusters[1].moments.covariance(0, 0), 0.01, 0.003);
}

TEST(ParticleClusters, OneBlobAcrossTheHeadingSeamIsOneCluster) {
  std::mt19937_64 rng(4);
  std::vector<WeightedPose> particles;
  add_blob(particles, {-0.25, 3.0, kPi}, 400, 1.0, rng);  // across x = 0 and heading +-pi
  const auto clusters = cluster_particles(particles, {});
  ASSERT_EQ(clusters.size(), 1U);
  EXPECT_NEAR(std::abs(clusters[0].moments.mean.theta), kPi, 0.02);
  EXPECT_LT(clusters[0].moments.covariance(2, 2), 0.01);
}

TEST(ParticleClusters, TheSamePlaceFacingAwayIsAnotherHypothesis) {
  std::vector<WeightedPose> particles = {{{0.0, 0.0, 0.0}, 1.0}, {{0.0, 0.0, kPi / 2.0}, 1.0}};
  EXPECT_EQ(cluster_particles(particles, {}).size(), 2U);
  EXPECT_TRUE(cluster_particles({}, {}).empty());
}

}  // namespace
}  // namespace mobot::estimation
