#include "core/slam/scan_refiner.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>

namespace mobot::slam {

namespace {

struct Evaluation {
  double cost = 0.0;
  double score = 0.0;
  Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();  // point term only, per point
  Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
};

Evaluation evaluate(const ProbabilityGrid& field, std::span<const geometry::Point2D> points,
                    const Eigen::Vector3d& x, const Eigen::Vector3d& x0,
                    const ScanRefinerOptions& options, bool with_derivatives) {
  Evaluation e;
  const double c = std::cos(x.z());
  const double s = std::sin(x.z());
  const double inv_n = 1.0 / static_cast<double>(points.size());
  double sum_r2 = 0.0;
  double sum_value = 0.0;
  for (const auto& p : points) {
    const double mx = x.x() + c * p.x - s * p.y;
    const double my = x.y() + s * p.x + c * p.y;
    const ProbabilityGrid::Sample sample = field.interpolate(mx, my);
    const double r = 1.0 - sample.value;
    sum_r2 += r * r;
    sum_value += sample.value;
    if (with_derivatives) {
      // r = 1 - M(T p): dr/dx = -dM/dx, dr/dtheta = -grad M . dR/dtheta p.
      const Eigen::Vector3d j(
          -sample.d_dx, -sample.d_dy,
          -(sample.d_dx * (-s * p.x - c * p.y) + sample.d_dy * (c * p.x - s * p.y)));
      e.jtj += j * j.transpose();
      e.jtr += j * r;
    }
  }
  e.score = sum_value * inv_n;
  const double wt2 = options.translation_weight * options.translation_weight;
  const double wr2 = options.rotation_weight * options.rotation_weight;
  const Eigen::Vector3d d = x - x0;
  e.cost = sum_r2 * inv_n + wt2 * (d.x() * d.x() + d.y() * d.y()) + wr2 * d.z() * d.z();
  e.jtj *= inv_n;
  e.jtr *= inv_n;
  return e;
}

}  // namespace

RefinedPose refine_scan_pose(const ProbabilityGrid& field,
                             std::span<const geometry::Point2D> points_in_base,
                             const geometry::Pose2D& initial_pose,
                             const ScanRefinerOptions& options) {
  return refine_scan_pose(field, points_in_base, initial_pose, initial_pose, options);
}

RefinedPose refine_scan_pose(const ProbabilityGrid& field,
                             std::span<const geometry::Point2D> points_in_base,
                             const geometry::Pose2D& initial_pose,
                             const geometry::Pose2D& prior_pose,
                             const ScanRefinerOptions& options) {
  if (options.max_iterations < 0 || !std::isfinite(options.translation_weight) ||
      !std::isfinite(options.rotation_weight) || !std::isfinite(options.min_step) ||
      options.translation_weight < 0.0 || options.rotation_weight < 0.0 || options.min_step < 0.0) {
    throw std::invalid_argument("ScanRefinerOptions: iterations, weights and step must be >= 0");
  }
  RefinedPose out;
  out.pose = initial_pose;
  if (points_in_base.empty() || field.empty() || !geometry::is_finite(initial_pose) ||
      !geometry::is_finite(prior_pose)) {
    return out;
  }

  // The prior's heading is unwrapped next to the start's, so the pull never goes the long way.
  const Eigen::Vector3d x0(
      prior_pose.x, prior_pose.y,
      initial_pose.theta + geometry::wrap_angle(prior_pose.theta - initial_pose.theta));
  Eigen::Vector3d x(initial_pose.x, initial_pose.y, initial_pose.theta);
  Evaluation current = evaluate(field, points_in_base, x, x0, options, true);
  const double wt2 = options.translation_weight * options.translation_weight;
  const double wr2 = options.rotation_weight * options.rotation_weight;
  const Eigen::Vector3d prior_diag(wt2, wt2, wr2);
  double lambda = 1e-4;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    out.iterations = iteration + 1;
    Eigen::Matrix3d h = current.jtj;
    h.diagonal() += prior_diag;
    const Eigen::Vector3d g = current.jtr + prior_diag.cwiseProduct(x - x0);
    bool improved = false;
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    for (int attempt = 0; attempt < 8 && !improved; ++attempt) {
      Eigen::Matrix3d damped = h;
      damped.diagonal() += lambda * (h.diagonal().array() + 1e-9).matrix();
      step = -damped.ldlt().solve(g);
      if (!step.allFinite()) break;
      // Derivatives come along: accepted trials are the common case.
      Evaluation trial = evaluate(field, points_in_base, x + step, x0, options, true);
      if (trial.cost < current.cost) {
        x += step;
        current = trial;
        lambda = std::max(lambda * 0.3, 1e-7);
        improved = true;
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved || step.norm() < options.min_step) break;
  }
  out.pose = {x.x(), x.y(), geometry::wrap_angle(x.z())};
  out.score = current.score;
  out.hessian = current.jtj;
  return out;
}

}  // namespace mobot::slam
