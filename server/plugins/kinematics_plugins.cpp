#include "server/plugins/kinematics_plugins.h"

#include "core/kinematics/differential_model.h"
#include "server/plugins/option_reader.h"

namespace mobot::server {

Registry<kinematics::KinematicModel>::Maker differential_plugin(const YAML::Node& section,
                                                                const PluginContext& context) {
  OptionReader(section, "kinematics.differential").done();
  const kinematics::DifferentialModelOptions options{context.geometry.wheel_radius_m,
                                                     context.geometry.track_m, context.limits};
  return [options] { return std::make_unique<kinematics::DifferentialModel>(options); };
}

}  // namespace mobot::server
