#pragma once

#include "core/slam/pose_graph.h"

namespace mobot::slam {

struct PoseGraphOptimizerOptions {
  // Levenberg-Marquardt iterations at most; a warm-started graph after one new closure usually
  // converges in 3-6.
  int max_iterations = 20;
  // Huber kernel on loop edges, on the Mahalanobis norm sqrt(e^T Omega e): beyond delta a loop edge
  // pulls with constant force, so one wrong closure bends the graph instead of tearing it.
  // 0: no kernel.
  double loop_huber_delta = 2.0;
  // Stop when an accepted step lowers the cost by less than this fraction.
  double min_relative_decrease = 1e-6;
  double initial_lambda = 1e-4;
};

struct OptimizationReport {
  int iterations = 0;
  double initial_cost = 0.0;  // sum of (robustified) squared Mahalanobis residuals
  double final_cost = 0.0;
};

// docs/algorithms.md E5: sparse Levenberg-Marquardt over all node poses but the first (fixed: it
// anchors the map frame). Each iteration linearises every edge (the analytic Jacobians of
// edge_residual), assembles the 3N x 3N normal equations as a sparse matrix and solves them with
// Eigen's SimplicialLDLT. Throws std::invalid_argument on negative options.
OptimizationReport optimize_pose_graph(PoseGraph& graph,
                                       const PoseGraphOptimizerOptions& options = {});

}  // namespace mobot::slam
