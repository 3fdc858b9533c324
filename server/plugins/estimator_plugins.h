#pragma once

#include "core/estimation/pose_estimator.h"
#include "server/plugins/registry.h"

namespace mobot::server {

// estimators.ekf: {fuse: [compass, lines, bearing]} (docs/algorithms.md E2)
Registry<estimation::PoseEstimator>::Maker ekf_plugin(const YAML::Node& section,
                                                      const PluginContext& context);
// estimators.odometry: the EKF predicting only: dead reckoning with its covariance. No options.
Registry<estimation::PoseEstimator>::Maker odometry_plugin(const YAML::Node& section,
                                                           const PluginContext& context);

}  // namespace mobot::server
