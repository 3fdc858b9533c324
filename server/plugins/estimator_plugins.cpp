#include "server/plugins/estimator_plugins.h"

#include "core/estimation/ekf_pose_estimator.h"
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

}  // namespace mobot::server
