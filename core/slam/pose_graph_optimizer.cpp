#include "core/slam/pose_graph_optimizer.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace mobot::slam {

namespace {

// Huber's rho on chi^2 = e^T Omega e and the IRLS weight rho'(chi^2).
struct Robust {
  double cost = 0.0;
  double weight = 1.0;
};

Robust robustify(double chi2, bool robust, double delta) {
  if (!robust || delta <= 0.0 || chi2 <= delta * delta) return {chi2, 1.0};
  const double norm = std::sqrt(chi2);
  return {2.0 * delta * norm - delta * delta, delta / norm};
}

double total_cost(const std::vector<geometry::Pose2D>& poses,
                  const std::vector<PoseGraphEdge>& edges, double delta) {
  double cost = 0.0;
  for (const PoseGraphEdge& edge : edges) {
    const Eigen::Vector3d e = edge_residual(poses[edge.from], poses[edge.to], edge.relative);
    cost += robustify(e.dot(edge.information * e), edge.kind == EdgeKind::kLoop, delta).cost;
  }
  return cost;
}

}  // namespace

OptimizationReport optimize_pose_graph(PoseGraph& graph, const PoseGraphOptimizerOptions& options) {
  if (options.max_iterations < 0 || !(options.loop_huber_delta >= 0.0) ||
      !(options.min_relative_decrease >= 0.0) || !(options.initial_lambda > 0.0) ||
      !std::isfinite(options.loop_huber_delta) || !std::isfinite(options.initial_lambda)) {
    throw std::invalid_argument("PoseGraphOptimizerOptions: iterations, delta, decrease >= 0");
  }
  OptimizationReport report;
  const std::vector<PoseGraphEdge>& edges = graph.edges();
  std::vector<geometry::Pose2D> poses = graph.poses();
  const double delta = options.loop_huber_delta;
  report.initial_cost = total_cost(poses, edges, delta);
  report.final_cost = report.initial_cost;
  const std::size_t n = poses.size();
  if (n < 2 || edges.empty()) return report;
  const auto unknowns = static_cast<Eigen::Index>(3 * (n - 1));

  double lambda = options.initial_lambda;
  double cost = report.initial_cost;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(edges.size() * 36);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  bool pattern_known = false;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    report.iterations = iteration + 1;
    triplets.clear();
    Eigen::VectorXd b = Eigen::VectorXd::Zero(unknowns);
    // Every diagonal entry exists, so the damping below never changes the sparsity pattern.
    for (Eigen::Index i = 0; i < unknowns; ++i) triplets.emplace_back(i, i, 0.0);
    for (const PoseGraphEdge& edge : edges) {
      const geometry::Pose2D& a = poses[edge.from];
      const geometry::Pose2D& c = poses[edge.to];
      const Eigen::Vector3d e = edge_residual(a, c, edge.relative);
      const Robust robust =
          robustify(e.dot(edge.information * e), edge.kind == EdgeKind::kLoop, delta);
      const Eigen::Matrix3d omega = robust.weight * edge.information;
      // e_t = Rz^T (Ra^T (t_c - t_a) - t_z), e_theta = theta_c - theta_a - theta_z.
      const double ca = std::cos(a.theta), sa = std::sin(a.theta);
      const double cz = std::cos(edge.relative.theta), sz = std::sin(edge.relative.theta);
      Eigen::Matrix2d rz_t;
      rz_t << cz, sz, -sz, cz;
      Eigen::Matrix2d ra_t;
      ra_t << ca, sa, -sa, ca;
      Eigen::Matrix2d dra_t;  // d(Ra^T)/d theta_a
      dra_t << -sa, ca, -ca, -sa;
      const Eigen::Vector2d d(c.x - a.x, c.y - a.y);
      Eigen::Matrix3d ja = Eigen::Matrix3d::Zero();
      Eigen::Matrix3d jc = Eigen::Matrix3d::Zero();
      ja.topLeftCorner<2, 2>() = -rz_t * ra_t;
      ja.topRightCorner<2, 1>() = rz_t * dra_t * d;
      ja(2, 2) = -1.0;
      jc.topLeftCorner<2, 2>() = rz_t * ra_t;
      jc(2, 2) = 1.0;
      const std::size_t blocks[2] = {edge.from, edge.to};
      const Eigen::Matrix3d* jacobians[2] = {&ja, &jc};
      for (int i = 0; i < 2; ++i) {
        if (blocks[i] == 0) continue;  // the fixed first node
        const auto row = static_cast<Eigen::Index>(3 * (blocks[i] - 1));
        b.segment<3>(row) += jacobians[i]->transpose() * omega * e;
        for (int j = 0; j < 2; ++j) {
          if (blocks[j] == 0) continue;
          const auto col = static_cast<Eigen::Index>(3 * (blocks[j] - 1));
          const Eigen::Matrix3d block = jacobians[i]->transpose() * omega * *jacobians[j];
          for (int r = 0; r < 3; ++r) {
            for (int k = 0; k < 3; ++k) triplets.emplace_back(row + r, col + k, block(r, k));
          }
        }
      }
    }
    Eigen::SparseMatrix<double> h(unknowns, unknowns);
    h.setFromTriplets(triplets.begin(), triplets.end());
    const Eigen::VectorXd diagonal = h.diagonal();
    if (!pattern_known) {
      solver.analyzePattern(h);
      pattern_known = true;
    }
    bool accepted = false;
    double decrease = 0.0;
    for (int attempt = 0; attempt < 10 && !accepted; ++attempt) {
      Eigen::SparseMatrix<double> damped = h;
      for (Eigen::Index i = 0; i < unknowns; ++i) {
        damped.coeffRef(i, i) += lambda * (diagonal(i) + 1e-9);
      }
      solver.factorize(damped);
      if (solver.info() != Eigen::Success) {
        lambda *= 10.0;
        continue;
      }
      const Eigen::VectorXd step = solver.solve(-b);
      if (!step.allFinite()) {
        lambda *= 10.0;
        continue;
      }
      std::vector<geometry::Pose2D> trial = poses;
      for (std::size_t node = 1; node < n; ++node) {
        const auto k = static_cast<Eigen::Index>(3 * (node - 1));
        trial[node].x += step(k);
        trial[node].y += step(k + 1);
        trial[node].theta = geometry::wrap_angle(trial[node].theta + step(k + 2));
      }
      const double trial_cost = total_cost(trial, edges, delta);
      if (trial_cost < cost) {
        decrease = (cost - trial_cost) / std::max(cost, 1e-300);
        poses = std::move(trial);
        cost = trial_cost;
        lambda = std::max(lambda / 10.0, 1e-12);
        accepted = true;
      } else {
        lambda *= 10.0;
      }
    }
    if (!accepted || decrease < options.min_relative_decrease) break;
  }
  report.final_cost = cost;
  graph.set_poses(std::move(poses));
  return report;
}

}  // namespace mobot::slam
