#pragma once

#include <span>

#include <Eigen/Core>

#include "core/geometry/pose2d.h"
#include "core/slam/probability_grid.h"

namespace mobot::slam {

struct ScanRefinerOptions {
  int max_iterations = 15;
  // Cost = mean over points of (1 - M(T p))^2 + w_t^2 |t - t0|^2 + w_r^2 (theta - theta0)^2, M the
  // bicubic field (Cartographer's CeresScanMatcher2D with its occupied-space, translation and
  // rotation weights, normalised per point). The pulls keep a featureless direction (a corridor's
  // axis) where the correlative search put it instead of letting it drift.
  double translation_weight = 0.1;  // per metre
  double rotation_weight = 0.1;     // per radian
  // Stop when a step moves less than this (metres, and radians times 1 m).
  double min_step = 1e-5;
};

struct RefinedPose {
  geometry::Pose2D pose;
  double score = 0.0;  // mean interpolated field value under the points, 0..1
  // Gauss-Newton approximation J^T J of the point term's Hessian (per point, not yet divided by a
  // noise variance): its inverse shape is the refinement's uncertainty.
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
  int iterations = 0;
};

// docs/algorithms.md E5: local refinement of a scan's pose on the smooth matching field by
// Levenberg-Marquardt-damped Gauss-Newton (Eigen, 3 unknowns). Returns the initial pose unchanged
// (score computed) for no points, an empty grid or a non-finite initial pose. Throws
// std::invalid_argument on negative or non-finite options.
RefinedPose refine_scan_pose(const ProbabilityGrid& field,
                             std::span<const geometry::Point2D> points_in_base,
                             const geometry::Pose2D& initial_pose,
                             const ScanRefinerOptions& options = {});
// The same, starting from `initial_pose` but pulled towards `prior_pose` (Cartographer pulls
// towards the motion prediction, not the correlative search's grid-quantised answer: along a
// corridor the field barely constrains the axis, and the search's whole-cell offset would stay).
RefinedPose refine_scan_pose(const ProbabilityGrid& field,
                             std::span<const geometry::Point2D> points_in_base,
                             const geometry::Pose2D& initial_pose,
                             const geometry::Pose2D& prior_pose,
                             const ScanRefinerOptions& options);

}  // namespace mobot::slam
