// estimators.particle_filter: every option reaches the filter, and a bad one is refused with its
// full key before anything is built.
#include <gtest/gtest.h>

#include <string>

#include "core/estimation/particle_filter/particle_filter_estimator.h"
#include "server/plugins/estimator_plugins.h"
#include "server/plugins/option_reader.h"

namespace mobot::server {
namespace {

std::string filter_error_of(const std::string& yaml) {
  try {
    particle_filter_plugin(YAML::Load(yaml), {});
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "";
}

const estimation::ParticleFilterOptions& options_of(const estimation::PoseEstimator& estimator) {
  return dynamic_cast<const estimation::ParticleFilterEstimator&>(estimator).filter().options();
}

TEST(ParticleFilterPlugin, DefaultsAreTheFiltersOwn) {
  const auto maker = particle_filter_plugin(YAML::Node(), {});
  const auto estimator = maker();
  ASSERT_NE(estimator, nullptr);
  EXPECT_EQ(estimator->name(), "particle_filter");
  EXPECT_EQ(estimator->method(), "particle_filter(laser)");
  const estimation::ParticleFilterOptions& options = options_of(*estimator);
  const estimation::ParticleFilterOptions defaults;
  EXPECT_EQ(options.kld.min_particles, defaults.kld.min_particles);
  EXPECT_EQ(options.kld.max_particles, defaults.kld.max_particles);
  EXPECT_EQ(options.laser.max_beams, defaults.laser.max_beams);
  EXPECT_EQ(options.seed, defaults.seed);
}

TEST(ParticleFilterPlugin, EveryOptionReachesTheFilter) {
  const auto estimator = particle_filter_plugin(YAML::Load(R"(
    min_particles: 500
    max_particles: 8000
    global_particles: 20000
    kld_epsilon: 0.02
    kld_z: 2.33
    update_min_translation_m: 0.1
    update_min_rotation_rad: 0.3
    alpha1: 0.01
    alpha2: 0.02
    alpha3: 0.03
    alpha4: 0.04
    max_beams: 90
    resample_interval: 2
    combination: cubed_sum
    product_exponent: 0.5
    kidnap_probability: 0.001
    off_map_log_penalty: 7
    converged_min_updates: 4
    z_hit: 0.9
    z_rand: 0.1
    sigma_hit_m: 0.1
    laser_max_range_m: 12
    no_return_beams: false
    no_return_margin_m: 0.5
    no_return_clearance_rad: 0.1
    no_return_weight: 0.6
    max_no_return_beams: 4
    max_weighed_per_update: 0
    likelihood_max_distance_m: 1.5
    recovery_alpha_slow: 0.002
    recovery_alpha_fast: 0.2
    recovery_min_fraction: 0.1
    converged_position_std_m: 0.2
    converged_heading_std_rad: 0.15
    converged_min_cluster_weight: 0.8
    seed: 77
  )"),
                                                {})();
  const estimation::ParticleFilterOptions& o = options_of(*estimator);
  EXPECT_EQ(o.kld.min_particles, 500U);
  EXPECT_EQ(o.kld.max_particles, 8000U);
  EXPECT_EQ(o.global_particles, 20000U);
  EXPECT_DOUBLE_EQ(o.kld.epsilon, 0.02);
  EXPECT_DOUBLE_EQ(o.kld.z_quantile, 2.33);
  EXPECT_DOUBLE_EQ(o.update_min_translation_m, 0.1);
  EXPECT_DOUBLE_EQ(o.update_min_rotation_rad, 0.3);
  EXPECT_DOUBLE_EQ(o.motion.alpha1, 0.01);
  EXPECT_DOUBLE_EQ(o.motion.alpha2, 0.02);
  EXPECT_DOUBLE_EQ(o.motion.alpha3, 0.03);
  EXPECT_DOUBLE_EQ(o.motion.alpha4, 0.04);
  EXPECT_EQ(o.laser.max_beams, 90);
  EXPECT_EQ(o.resample_interval, 2);
  EXPECT_EQ(o.laser.combination, estimation::BeamCombination::kCubedSum);
  EXPECT_DOUBLE_EQ(o.laser.product_exponent, 0.5);
  EXPECT_DOUBLE_EQ(o.kidnap_probability, 0.001);
  EXPECT_DOUBLE_EQ(o.off_map_log_penalty, 7.0);
  EXPECT_EQ(o.converged_min_updates, 4);
  EXPECT_DOUBLE_EQ(o.laser.z_hit, 0.9);
  EXPECT_DOUBLE_EQ(o.laser.z_rand, 0.1);
  EXPECT_DOUBLE_EQ(o.laser.sigma_hit_m, 0.1);
  EXPECT_DOUBLE_EQ(o.laser.range_max_m, 12.0);
  EXPECT_FALSE(o.laser.no_return_beams);
  EXPECT_DOUBLE_EQ(o.laser.no_return_margin_m, 0.5);
  EXPECT_DOUBLE_EQ(o.laser.no_return_clearance_rad, 0.1);
  EXPECT_DOUBLE_EQ(o.laser.no_return_weight, 0.6);
  EXPECT_EQ(o.laser.max_no_return_beams, 4);
  EXPECT_EQ(o.max_weighed_per_update, 0U);
  EXPECT_DOUBLE_EQ(o.field.max_distance_m, 1.5);
  EXPECT_DOUBLE_EQ(o.alpha_slow, 0.002);
  EXPECT_DOUBLE_EQ(o.alpha_fast, 0.2);
  EXPECT_DOUBLE_EQ(o.recovery_min_fraction, 0.1);
  EXPECT_DOUBLE_EQ(o.converged_position_std_m, 0.2);
  EXPECT_DOUBLE_EQ(o.converged_heading_std_rad, 0.15);
  EXPECT_DOUBLE_EQ(o.converged_min_cluster_weight, 0.8);
  EXPECT_EQ(o.seed, 77U);
}

TEST(ParticleFilterPlugin, RefusesBadOptionsNamingTheKey) {
  const char* const bad[][2] = {
      {"{min_particles: 0}", "estimators.particle_filter.min_particles"},
      {"{max_particles: 5000000}", "estimators.particle_filter.max_particles"},
      {"{global_particles: 0}", "estimators.particle_filter.global_particles"},
      {"{min_particles: 3000, max_particles: 2500}", "estimators.particle_filter.min_particles"},
      {"{kld_epsilon: 0}", "estimators.particle_filter.kld_epsilon"},
      {"{kld_z: -1}", "estimators.particle_filter.kld_z"},
      {"{update_min_translation_m: -0.1}", "estimators.particle_filter.update_min_translation_m"},
      {"{update_min_rotation_rad: 4}", "estimators.particle_filter.update_min_rotation_rad"},
      {"{alpha1: -0.2}", "estimators.particle_filter.alpha1"},
      {"{alpha4: .nan}", "estimators.particle_filter.alpha4"},
      {"{max_beams: 1}", "estimators.particle_filter.max_beams"},
      {"{z_hit: 1.5}", "estimators.particle_filter.z_hit"},
      {"{z_rand: -0.5}", "estimators.particle_filter.z_rand"},
      {"{sigma_hit_m: 0}", "estimators.particle_filter.sigma_hit_m"},
      {"{laser_max_range_m: .inf}", "estimators.particle_filter.laser_max_range_m"},
      {"{no_return_beams: maybe}", "estimators.particle_filter.no_return_beams"},
      {"{no_return_margin_m: -1}", "estimators.particle_filter.no_return_margin_m"},
      {"{no_return_clearance_rad: 2}", "estimators.particle_filter.no_return_clearance_rad"},
      {"{no_return_weight: 1.1}", "estimators.particle_filter.no_return_weight"},
      {"{max_no_return_beams: -1}", "estimators.particle_filter.max_no_return_beams"},
      {"{max_weighed_per_update: -5}", "estimators.particle_filter.max_weighed_per_update"},
      {"{likelihood_max_distance_m: 0}", "estimators.particle_filter.likelihood_max_distance_m"},
      {"{recovery_alpha_slow: 2}", "estimators.particle_filter.recovery_alpha_slow"},
      {"{recovery_alpha_fast: -1}", "estimators.particle_filter.recovery_alpha_fast"},
      {"{recovery_min_fraction: 1}", "estimators.particle_filter.recovery_min_fraction"},
      {"{off_map_log_penalty: -1}", "estimators.particle_filter.off_map_log_penalty"},
      {"{converged_position_std_m: 0}", "estimators.particle_filter.converged_position_std_m"},
      {"{converged_heading_std_rad: 7}", "estimators.particle_filter.converged_heading_std_rad"},
      {"{converged_min_cluster_weight: 0}",
       "estimators.particle_filter.converged_min_cluster_weight"},
      {"{seed: -3}", "estimators.particle_filter.seed"},
      {"{resample_interval: 0}", "estimators.particle_filter.resample_interval"},
      {"{combination: sum}", "estimators.particle_filter.combination: 'sum'"},
      {"{combination: [product]}", "estimators.particle_filter.combination"},
      {"{product_exponent: 1.5}", "estimators.particle_filter.product_exponent"},
      {"{kidnap_probability: -0.1}", "estimators.particle_filter.kidnap_probability"},
      {"{converged_min_updates: 0}", "estimators.particle_filter.converged_min_updates"},
      {"{seed: many}", "estimators.particle_filter.seed"},
      {"{sigma_hit: 0.2}", "estimators.particle_filter.sigma_hit: unknown key"},
      {"[1, 2]", "estimators.particle_filter: expected a mapping"},
  };
  for (const auto& [yaml, key] : bad) {
    const std::string message = filter_error_of(yaml);
    EXPECT_NE(message.find(key), std::string::npos) << yaml << " -> '" << message << "'";
  }
  EXPECT_EQ(filter_error_of("{min_particles: 100, max_particles: 100}"), "");
}

}  // namespace
}  // namespace mobot::server
