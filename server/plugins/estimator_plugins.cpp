#include "server/plugins/estimator_plugins.h"

#include <numbers>

#include "core/estimation/ekf_pose_estimator.h"
#include "core/estimation/landmark_pose_estimator.h"
#include "core/estimation/particle_filter/particle_filter_estimator.h"
#include "server/plugins/option_reader.h"

namespace mobot::server {
namespace {

void read_fuse(OptionReader& reader, estimation::EkfPoseEstimatorOptions& options) {
  const YAML::Node fuse = reader.node("fuse");
  if (!fuse) return;
  const std::string where = reader.path() + ".fuse";
  if (!fuse.IsSequence()) throw ConfigError(where + ": expected a list of compass, lines, bearing");
  options.fuse_compass = options.fuse_lines = options.fuse_bearing = false;
  for (const auto& item : fuse) {
    const auto name = item.as<std::string>();
    if (name == "compass") {
      options.fuse_compass = true;
    } else if (name == "lines") {
      options.fuse_lines = true;
    } else if (name == "bearing") {
      options.fuse_bearing = true;
    } else {
      throw ConfigError(where + ": '" + name + "' is not one of compass, lines, bearing");
    }
  }
}

void read_combination(OptionReader& reader, estimation::BeamLikelihoodOptions& options) {
  const YAML::Node node = reader.node("combination");
  if (!node) return;
  const std::string where = reader.path() + ".combination";
  std::string name;
  try {
    name = node.as<std::string>();
  } catch (const YAML::Exception&) {
    throw ConfigError(where + ": expected product or cubed_sum");
  }
  if (name == "product") {
    options.combination = estimation::BeamCombination::kProduct;
  } else if (name == "cubed_sum") {
    options.combination = estimation::BeamCombination::kCubedSum;
  } else {
    throw ConfigError(where + ": '" + name + "' is not one of product, cubed_sum");
  }
}

}  // namespace

Registry<estimation::PoseEstimator>::Maker ekf_plugin(const YAML::Node& section,
                                                      const PluginContext&) {
  estimation::EkfPoseEstimatorOptions options;
  OptionReader reader(section, "estimators.ekf");
  read_fuse(reader, options);
  reader.number("compass_var_rad2", options.filter.compass_var_rad2, 1e-9, 1.0);
  reader.number("bearing_var_rad2", options.filter.bearing_var_rad2, 1e-9, 1.0);
  reader.done();
  return [options] { return std::make_unique<estimation::EkfPoseEstimator>(options); };
}

Registry<estimation::PoseEstimator>::Maker odometry_plugin(const YAML::Node& section,
                                                           const PluginContext&) {
  OptionReader(section, "estimators.odometry").done();
  estimation::EkfPoseEstimatorOptions options;
  options.name = "odometry";
  options.fuse_compass = options.fuse_lines = options.fuse_bearing = false;
  return [options] { return std::make_unique<estimation::EkfPoseEstimator>(options); };
}

estimation::ParticleFilterOptions read_particle_filter_options(const YAML::Node& section) {
  estimation::ParticleFilterOptions filter;
  OptionReader reader(section, "estimators.particle_filter");
  int min_particles = static_cast<int>(filter.kld.min_particles);
  int max_particles = static_cast<int>(filter.kld.max_particles);
  reader.integer("min_particles", min_particles, 10, 1000000);
  reader.integer("max_particles", max_particles, 10, 1000000);
  if (min_particles > max_particles) {
    throw ConfigError(reader.path() + ".min_particles: " + std::to_string(min_particles) +
                      " is above max_particles (" + std::to_string(max_particles) + ")");
  }
  filter.kld.min_particles = static_cast<std::size_t>(min_particles);
  filter.kld.max_particles = static_cast<std::size_t>(max_particles);
  int global_particles = static_cast<int>(filter.global_particles);
  reader.integer("global_particles", global_particles, 10, 10000000);
  filter.global_particles = static_cast<std::size_t>(global_particles);
  reader.number("global_search_exponent", filter.global_search_exponent, 0.001, 1.0);
  int weighed_per_update = static_cast<int>(filter.max_weighed_per_update);
  reader.integer("max_weighed_per_update", weighed_per_update, 0, 10000000);
  filter.max_weighed_per_update = static_cast<std::size_t>(weighed_per_update);
  reader.number("kld_epsilon", filter.kld.epsilon, 1e-4, 1.0);
  reader.number("kld_z", filter.kld.z_quantile, 0.0, 10.0);
  reader.number("update_min_translation_m", filter.update_min_translation_m, 0.0, 10.0);
  reader.number("update_min_rotation_rad", filter.update_min_rotation_rad, 0.0, std::numbers::pi);
  reader.number("alpha1", filter.motion.alpha1, 0.0, 10.0);
  reader.number("alpha2", filter.motion.alpha2, 0.0, 10.0);
  reader.number("alpha3", filter.motion.alpha3, 0.0, 10.0);
  reader.number("alpha4", filter.motion.alpha4, 0.0, 10.0);
  reader.integer("resample_interval", filter.resample_interval, 1, 100);
  reader.integer("max_beams", filter.laser.max_beams, 2, 10000);
  read_combination(reader, filter.laser);
  reader.number("product_exponent", filter.laser.product_exponent, 0.001, 1.0);
  reader.number("z_hit", filter.laser.z_hit, 0.0, 1.0);
  reader.number("z_rand", filter.laser.z_rand, 0.0, 1.0);
  reader.number("sigma_hit_m", filter.laser.sigma_hit_m, 0.001, 10.0);
  reader.number("laser_max_range_m", filter.laser.range_max_m, 0.1, 1000.0);
  reader.flag("no_return_beams", filter.laser.no_return_beams);
  reader.number("no_return_margin_m", filter.laser.no_return_margin_m, 0.0, 10.0);
  reader.integer("max_no_return_beams", filter.laser.max_no_return_beams, 0, 10000);
  reader.number("no_return_clearance_rad", filter.laser.no_return_clearance_rad, 0.0, 1.0);
  reader.number("no_return_weight", filter.laser.no_return_weight, 0.0, 1.0);
  reader.number("likelihood_max_distance_m", filter.field.max_distance_m, 0.01, 20.0);
  reader.number("recovery_alpha_slow", filter.alpha_slow, 0.0, 1.0);
  reader.number("recovery_alpha_fast", filter.alpha_fast, 0.0, 1.0);
  reader.number("recovery_min_fraction", filter.recovery_min_fraction, 0.0, 0.99);
  reader.number("kidnap_probability", filter.kidnap_probability, 0.0, 1.0);
  reader.number("off_map_log_penalty", filter.off_map_log_penalty, 0.0, 1000.0);
  reader.number("converged_position_std_m", filter.converged_position_std_m, 0.001, 100.0);
  reader.number("converged_heading_std_rad", filter.converged_heading_std_rad, 0.001,
                std::numbers::pi);
  reader.number("converged_min_cluster_weight", filter.converged_min_cluster_weight, 0.01, 1.0);
  reader.integer("converged_min_updates", filter.converged_min_updates, 1, 1000);
  int seed = static_cast<int>(filter.seed);
  reader.integer("seed", seed, 0, 2147483647);
  filter.seed = static_cast<std::uint64_t>(seed);
  reader.done();
  return filter;
}

Registry<estimation::PoseEstimator>::Maker particle_filter_plugin(const YAML::Node& section,
                                                                  const PluginContext&) {
  estimation::ParticleFilterEstimatorOptions options;
  options.filter = read_particle_filter_options(section);
  return [options] { return std::make_unique<estimation::ParticleFilterEstimator>(options); };
}

Registry<estimation::PoseEstimator>::Maker landmark_ekf_plugin(const YAML::Node& section,
                                                               const PluginContext& context) {
  estimation::LandmarkPoseEstimatorOptions options;
  if (context.geometry.wheelbase_m > 0.0) options.filter.wheelbase_m = context.geometry.wheelbase_m;
  OptionReader reader(section, "estimators.landmark_ekf");
  reader.number("wheelbase_m", options.filter.wheelbase_m, 0.1, 10.0);
  reader.number("speed_sigma_mps", options.filter.speed_sigma_mps, 1e-4, 10.0);
  reader.number("steer_sigma_rad", options.filter.steer_sigma_rad, 1e-5, 1.0);
  reader.number("range_sigma_m", options.filter.range_sigma_m, 1e-4, 10.0);
  reader.number("bearing_sigma_rad", options.filter.bearing_sigma_rad, 1e-5, 1.0);
  reader.number("predict_period_s", options.predict_period_s, 0.01, 1.0);
  bool midpoint = options.filter.integration == estimation::TricycleIntegration::kMidpoint;
  reader.flag("midpoint_integration", midpoint);
  options.filter.integration =
      midpoint ? estimation::TricycleIntegration::kMidpoint : estimation::TricycleIntegration::kEuler;
  reader.done();
  return [options] { return std::make_unique<estimation::LandmarkPoseEstimator>(options); };
}

}  // namespace mobot::server
