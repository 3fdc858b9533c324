#pragma once

#include "core/estimation/particle_filter/particle_filter.h"
#include "core/estimation/pose_estimator.h"
#include "server/plugins/registry.h"

namespace mobot::server {

// estimators.ekf: {fuse: [compass, lines, bearing]} (docs/algorithms.md E2)
Registry<estimation::PoseEstimator>::Maker ekf_plugin(const YAML::Node& section,
                                                      const PluginContext& context);
// estimators.odometry: the EKF predicting only: dead reckoning with its covariance. No options.
Registry<estimation::PoseEstimator>::Maker odometry_plugin(const YAML::Node& section,
                                                           const PluginContext& context);
// estimators.particle_filter: AMCL's parameters (docs/algorithms.md E4) under the names of
// core/estimation/particle_filter/particle_filter.h: min_particles, max_particles,
// global_particles, kld_epsilon, kld_z, update_min_translation_m, update_min_rotation_rad,
// resample_interval, alpha1..alpha4, max_beams, combination (product | cubed_sum),
// product_exponent, z_hit, z_rand, sigma_hit_m, laser_max_range_m, likelihood_max_distance_m,
// recovery_alpha_slow, recovery_alpha_fast, kidnap_probability, converged_position_std_m,
// converged_heading_std_rad, converged_min_cluster_weight, converged_min_updates, seed.
// Throws ConfigError naming the key for a value out of range or an unknown key.
estimation::ParticleFilterOptions read_particle_filter_options(const YAML::Node& section);
Registry<estimation::PoseEstimator>::Maker particle_filter_plugin(const YAML::Node& section,
                                                                  const PluginContext& context);

// estimators.landmark_ekf (docs/algorithms.md E3): the filter's sigmas, its prediction period and
// integration; the wheelbase defaults to the robot's.
Registry<estimation::PoseEstimator>::Maker landmark_ekf_plugin(const YAML::Node& section,
                                                               const PluginContext& context);

}  // namespace mobot::server
