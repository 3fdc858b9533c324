#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/estimation/line_measurement_model.h"
#include "core/geometry/pose2d.h"
#include "core/perception/line_segment.h"

namespace mobot::estimation {

struct LineMatcherOptions {
  // Hard gates on the innovation (docs/algorithms.md E2's |d rho|, |d psi| thresholds).
  double gate_rho_m = 0.5;
  double gate_alpha_rad = 0.35;
  // Mahalanobis gate on (d rho, d psi): chi-square with 2 dof, 99 %.
  double gate_mahalanobis2 = 9.21;
  // E2's endpoint-distance-sum criterion, used when both segments have endpoints: each observed
  // endpoint e, put in the map frame with the pose estimate, must satisfy
  // |e - a| + |e - b| - |b - a| < endpoint_gate_m for the map segment a-b, i.e. lie inside an
  // ellipse around it (a point beyond an end by u adds 2u). <= 0 disables it.
  double endpoint_gate_m = 0.6;
  // Added to every observed line's covariance: the map line's own error and the wall roughness the
  // scan fit cannot see. Defaults are E2's smallest measured var(r) and var(psi).
  double map_var_rho_m2 = 1e-4;
  double map_var_alpha_rad2 = 1e-4;
};

// An observed line associated with a map line, with everything the EKF update needs.
struct LineMatch {
  int observed_index = 0;
  int map_index = 0;
  LineMeasurementPrediction prediction;
  Eigen::Vector2d innovation = Eigen::Vector2d::Zero();  // (rho, alpha) observed - predicted
  Eigen::Matrix2d noise = Eigen::Matrix2d::Zero();       // R: observed covariance + map terms
  double mahalanobis2 = 0.0;
};

// The measurement noise R of one observed line, map terms included.
Eigen::Matrix2d line_measurement_noise(const perception::LineSegment& observed,
                                       const LineMatcherOptions& options);

// Associates each observed line (base frame) with at most one map line (map frame): among the map
// lines that pass every gate, the nearest in the Mahalanobis sense with S = H P H^T + R. Several
// observations may share one map line (a wall seen on both sides of a doorway). Lines that are
// not valid (see perception::is_valid) are never matched. Results are in observation order.
std::vector<LineMatch> match_lines(const geometry::Pose2D& pose, const Eigen::Matrix3d& covariance,
                                   const std::vector<perception::LineSegment>& observed_in_base,
                                   const std::vector<perception::LineSegment>& map_lines,
                                   const LineMatcherOptions& options = {});

}  // namespace mobot::estimation
