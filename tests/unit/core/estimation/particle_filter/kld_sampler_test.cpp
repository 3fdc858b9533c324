#include "core/estimation/particle_filter/kld_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>

namespace mobot::estimation {
namespace {

KldSamplerOptions unclamped(double epsilon, double z) {
  KldSamplerOptions options;
  options.epsilon = epsilon;
  options.z_quantile = z;
  options.min_particles = 1;
  options.max_particles = 1000000;
  return options;
}

TEST(KldParticleCount, MatchesFoxsBoundAtKnownValues) {
  // ceil((k-1)/(2 eps) (1 - 2/(9(k-1)) + sqrt(2/(9(k-1))) z)^3), evaluated independently.
  const KldSamplerOptions task = unclamped(0.05, 0.99);
  EXPECT_EQ(kld_particle_count(2, task), 20U);
  EXPECT_EQ(kld_particle_count(10, task), 131U);
  EXPECT_EQ(kld_particle_count(100, task), 1129U);
  EXPECT_EQ(kld_particle_count(1000, task), 10433U);
  // AMCL's pf.c defaults (pop_err 0.01, pop_z 3).
  const KldSamplerOptions amcl = unclamped(0.01, 3.0);
  EXPECT_EQ(kld_particle_count(2, amcl), 527U);
  EXPECT_EQ(kld_particle_count(100, amcl), 7332U);
  // Fox's delta = 0.01 (z = 2.326).
  EXPECT_EQ(kld_particle_count(50, unclamped(0.05, 2.326)), 750U);
}

TEST(KldParticleCount, IsClampedToTheLimits) {
  const KldSamplerOptions defaults;  // 2000 .. 5000
  EXPECT_EQ(kld_particle_count(0, defaults), 2000U);
  EXPECT_EQ(kld_particle_count(1, defaults), 2000U);
  EXPECT_EQ(kld_particle_count(100, defaults), 2000U);
  EXPECT_EQ(kld_particle_count(250, defaults), 2711U);
  EXPECT_EQ(kld_particle_count(500, defaults), 5000U);
  EXPECT_EQ(kld_particle_count(std::numeric_limits<std::size_t>::max() / 2, defaults), 5000U);
}

// Uniform over [0, extent_m)^2 with any heading.
std::vector<WeightedPose> spread(std::size_t count, double extent_m, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, extent_m);
  std::uniform_real_distribution<double> h(-std::numbers::pi, std::numbers::pi);
  std::vector<WeightedPose> out;
  for (std::size_t i = 0; i < count; ++i) out.push_back({{u(rng), u(rng), h(rng)}, 1.0});
  return out;
}

TEST(KldSampler, ATightCloudGetsTheMinimumAWideOneTheMaximum) {
  const KldSampler sampler;
  std::mt19937_64 rng(1);
  const auto tight = sampler.resample(spread(3000, 0.4, 1), 0.0, {}, rng);
  EXPECT_EQ(tight.size(), 2000U);
  const auto wide = sampler.resample(spread(3000, 20.0, 2), 0.0, {}, rng);
  EXPECT_EQ(wide.size(), 5000U);
  // In between (3 x 3 x 36 bins), the size is the fixed point: enough for the bins its own draw
  // fills.
  const auto middle = sampler.resample(spread(4000, 1.5, 3), 0.0, {}, rng);
  EXPECT_GT(middle.size(), 2000U);
  EXPECT_LT(middle.size(), 5000U);
  EXPECT_GE(middle.size(), kld_particle_count(count_occupied_bins(middle, sampler.options().bins),
                                              sampler.options()));
  for (const auto& p : middle) EXPECT_DOUBLE_EQ(p.weight, 1.0 / static_cast<double>(middle.size()));
}

TEST(KldSampler, LowVarianceDrawCopiesEachParticleInProportionToItsWeight) {
  KldSamplerOptions options;
  options.min_particles = options.max_particles = 1000;
  const KldSampler sampler(options);
  const std::vector<WeightedPose> particles = {{{0.0, 0.0, 0.0}, 0.5},
                                               {{1.0, 0.0, 0.0}, 0.0},
                                               {{2.0, 0.0, 0.0}, 0.3},
                                               {{3.0, 0.0, 0.0}, 0.2}};
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const auto drawn = sampler.resample(particles, 0.0, {}, rng);
    ASSERT_EQ(drawn.size(), 1000U);
    std::map<double, int> copies;
    for (const auto& p : drawn) ++copies[p.pose.x];
    // A systematic draw is off by at most one copy; a multinomial one by about 15.
    EXPECT_NEAR(copies[0.0], 500, 1);
    EXPECT_EQ(copies.count(1.0), 0U);
    EXPECT_NEAR(copies[2.0], 300, 1);
    EXPECT_NEAR(copies[3.0], 200, 1);
  }
}

TEST(KldSampler, InjectsRandomPosesAtTheRequestedRate) {
  KldSamplerOptions options;
  options.min_particles = options.max_particles = 4000;
  const KldSampler sampler(options);
  const std::vector<WeightedPose> particles = {{{0.0, 0.0, 0.0}, 1.0}};
  const RandomPoseFn far_away = [](std::mt19937_64&) { return geometry::Pose2D{100.0, 0.0, 0.0}; };
  std::mt19937_64 rng(3);
  int injected = 0;
  for (const auto& p : sampler.resample(particles, 0.25, far_away, rng)) injected += p.pose.x > 50;
  EXPECT_NEAR(injected, 1000, 120);  // binomial: sd 27
  for (const auto& p : sampler.resample(particles, 1.0, far_away, rng)) EXPECT_EQ(p.pose.x, 100.0);
  // Out-of-range fractions are clamped; without a generator nothing is injected.
  for (const auto& p : sampler.resample(particles, -3.0, far_away, rng)) EXPECT_EQ(p.pose.x, 0.0);
  for (const auto& p : sampler.resample(particles, 0.9, {}, rng)) EXPECT_EQ(p.pose.x, 0.0);
  for (const auto& p :
       sampler.resample(particles, std::numeric_limits<double>::quiet_NaN(), far_away, rng)) {
    EXPECT_EQ(p.pose.x, 0.0);
  }
}

TEST(KldSampler, RandomPosesCarryTheirImportanceWeight) {
  KldSamplerOptions options;
  options.min_particles = options.max_particles = 2000;
  const KldSampler sampler(options);
  const std::vector<WeightedPose> particles = {{{0.0, 0.0, 0.0}, 1.0}};
  const RandomPoseFn far_away = [](std::mt19937_64&) { return geometry::Pose2D{100.0, 0.0, 0.0}; };
  std::mt19937_64 rng(5);
  const auto drawn = sampler.resample(particles, 0.5, far_away, rng, 0.01);
  double random_weight = 0.0;
  double drawn_weight = 0.0;
  double total = 0.0;
  int random_count = 0;
  for (const auto& p : drawn) {
    total += p.weight;
    if (p.pose.x > 50.0) {
      random_weight = p.weight;
      ++random_count;
    } else {
      drawn_weight = p.weight;
    }
  }
  EXPECT_NEAR(total, 1.0, 1e-9);
  EXPECT_GT(random_count, 900);
  EXPECT_NEAR(random_weight / drawn_weight, 0.01, 1e-12);
  // Weights outside (0, 1] mean 1: the random poses weigh like the others.
  for (const double bad : {0.0, -1.0, 2.0, std::numeric_limits<double>::quiet_NaN()}) {
    for (const auto& p : sampler.resample(particles, 0.5, far_away, rng, bad)) {
      EXPECT_DOUBLE_EQ(p.weight, 1.0 / 2000.0);
    }
  }
}

TEST(KldSampler, BadWeightsAreTakenAsUniformAndNoParticlesGiveNone) {
  KldSamplerOptions options;
  options.min_particles = options.max_particles = 300;
  const KldSampler sampler(options);
  std::mt19937_64 rng(9);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double bad : {0.0, nan, -1.0}) {
    const std::vector<WeightedPose> particles = {
        {{0.0, 0.0, 0.0}, bad}, {{1.0, 0.0, 0.0}, bad}, {{2.0, 0.0, 0.0}, bad}};
    std::map<double, int> copies;
    for (const auto& p : sampler.resample(particles, 0.0, {}, rng)) ++copies[p.pose.x];
    EXPECT_NEAR(copies[0.0], 100, 1);
    EXPECT_NEAR(copies[1.0], 100, 1);
    EXPECT_NEAR(copies[2.0], 100, 1);
  }
  // One NaN among good weights is dropped, not spread.
  const std::vector<WeightedPose> mixed = {{{0.0, 0.0, 0.0}, 1.0}, {{1.0, 0.0, 0.0}, nan}};
  for (const auto& p : sampler.resample(mixed, 0.0, {}, rng)) EXPECT_EQ(p.pose.x, 0.0);
  EXPECT_TRUE(sampler.resample({}, 0.0, {}, rng).empty());
}

TEST(KldSampler, IsDeterministicForASeed) {
  const KldSampler sampler;
  const auto particles = spread(2500, 3.0, 4);
  std::mt19937_64 a(42);
  std::mt19937_64 b(42);
  const auto first = sampler.resample(
      particles, 0.1,
      [](std::mt19937_64& rng) {
        return geometry::Pose2D{std::uniform_real_distribution<double>(0.0, 1.0)(rng), 0.0, 0.0};
      },
      a);
  const auto second = sampler.resample(
      particles, 0.1,
      [](std::mt19937_64& rng) {
        return geometry::Pose2D{std::uniform_real_distribution<double>(0.0, 1.0)(rng), 0.0, 0.0};
      },
      b);
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i) EXPECT_EQ(first[i].pose, second[i].pose);
}

TEST(KldSampler, RefusesBadOptions) {
  KldSamplerOptions options;
  options.epsilon = 0.0;
  EXPECT_THROW(KldSampler{options}, std::invalid_argument);
  options = {};
  options.min_particles = 0;
  EXPECT_THROW(KldSampler{options}, std::invalid_argument);
  options = {};
  options.min_particles = 6000;
  EXPECT_THROW(KldSampler{options}, std::invalid_argument);
  options = {};
  options.bins.theta_rad = -1.0;
  EXPECT_THROW(KldSampler{options}, std::invalid_argument);
  options = {};
  options.z_quantile = std::numeric_limits<double>::infinity();
  EXPECT_THROW(KldSampler{options}, std::invalid_argument);
}

}  // namespace
}  // namespace mobot::estimation
