#include "server/plugins/kinematics_plugins.h"

#include "core/kinematics/differential_model.h"
#include "core/kinematics/tricycle_model.h"
#include "server/plugins/option_reader.h"

namespace mobot::server {
namespace {

Registry<kinematics::KinematicModel>::Maker tricycle_plugin(kinematics::TricycleType type,
                                                            const std::string& path,
                                                            const YAML::Node& section,
                                                            const PluginContext& context) {
  kinematics::TricycleModelOptions options;
  options.geometry.type = type;
  if (context.geometry.wheelbase_m > 0.0) options.geometry.wheelbase_m = context.geometry.wheelbase_m;
  options.limits.max_linear_mps = context.limits.max_linear_mps;
  options.limits.max_angular_radps = context.limits.max_angular_radps;
  options.limits.max_accel_mps2 = context.limits.max_linear_accel_mps2;
  OptionReader reader(section, path);
  reader.flag("saturate", options.limits.saturate);
  reader.number("max_steer_rad", options.limits.max_steer_rad, 0.05, 1.4);
  reader.number("wheelbase_m", options.geometry.wheelbase_m, 0.1, 10.0);
  reader.done();
  return [options] { return std::make_unique<kinematics::TricycleModel>(options); };
}

}  // namespace

Registry<kinematics::KinematicModel>::Maker tricycle_t1_plugin(const YAML::Node& section,
                                                               const PluginContext& context) {
  return tricycle_plugin(kinematics::TricycleType::kType1, "kinematics.tricycle_t1", section,
                         context);
}

Registry<kinematics::KinematicModel>::Maker tricycle_t2_plugin(const YAML::Node& section,
                                                               const PluginContext& context) {
  return tricycle_plugin(kinematics::TricycleType::kType2, "kinematics.tricycle_t2", section,
                         context);
}

Registry<kinematics::KinematicModel>::Maker differential_plugin(const YAML::Node& section,
                                                                const PluginContext& context) {
  OptionReader(section, "kinematics.differential").done();
  const kinematics::DifferentialModelOptions options{context.geometry.wheel_radius_m,
                                                     context.geometry.track_m, context.limits};
  return [options] { return std::make_unique<kinematics::DifferentialModel>(options); };
}

}  // namespace mobot::server
