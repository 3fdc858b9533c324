#pragma once

#include <Eigen/Core>
#include <optional>

#include "core/geometry/pose2d.h"

namespace mobot::estimation {

// A scalar measurement of a point landmark predicted from the pose, and dz / d(x, y, theta).
struct ScalarMeasurementPrediction {
  double z = 0.0;
  Eigen::RowVector3d h = Eigen::RowVector3d::Zero();
};

// Bearing of the landmark from the base, relative to its heading (docs/algorithms.md E2 set 3, E3):
// g = atan2(y_m - y, x_m - x) - theta, wrapped; H = [(y_m - y)/d^2, -(x_m - x)/d^2, -1].
// nullopt when the pose sits on the landmark (the bearing is undefined there).
std::optional<ScalarMeasurementPrediction> predict_bearing(const geometry::Pose2D& pose,
                                                           const geometry::Point2D& landmark);

// Distance from the base to the landmark (E3): r = |p - L|, H = [(x - x_m)/r, (y - y_m)/r, 0].
// nullopt on the landmark.
std::optional<ScalarMeasurementPrediction> predict_range(const geometry::Pose2D& pose,
                                                         const geometry::Point2D& landmark);

}  // namespace mobot::estimation
