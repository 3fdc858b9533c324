#pragma once

#include <Eigen/Core>
#include <span>

#include "core/estimation/weighted_pose.h"
#include "core/geometry/pose2d.h"

namespace mobot::estimation {

// The weighted mean and covariance of a set of poses.
struct PoseMoments {
  double weight = 0.0;  // the sum of the weights
  geometry::Pose2D mean;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

// docs/algorithms.md E4: x and y are plain weighted means; the heading is the circular mean
// atan2(sum w sin, sum w cos), and the covariance takes heading deviations wrapped about it, so a
// cloud straddling +-pi has a small spread, not one of pi. Weights need not be normalised; a set
// whose weights do not sum to a positive number gives zero moments.
PoseMoments weighted_pose_moments(std::span<const WeightedPose> poses);

}  // namespace mobot::estimation
