#include "core/slam/loop_closer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/LU>

#include "core/slam/correlative_scan_matcher.h"

namespace mobot::slam {

LoopCloser::LoopCloser(const LoopCloserOptions& options) : options_(options) {
  const double values[] = {options.search_radius_m,
                           options.min_chain_distance_m,
                           options.linear_window_m,
                           options.angular_window_rad,
                           options.min_score,
                           options.max_refine_shift_m,
                           options.max_refine_shift_rad,
                           options.max_position_std_m,
                           options.covariance_scale};
  for (double v : values) {
    if (!std::isfinite(v) || v < 0.0) {
      throw std::invalid_argument("LoopCloserOptions: values must be finite and >= 0");
    }
  }
  if (options.min_node_gap < 1 || options.submap_half_nodes < 0 || options.max_candidates < 0 ||
      !(options.covariance_scale > 0.0)) {
    throw std::invalid_argument("LoopCloserOptions: node gap >= 1, counts >= 0, scale > 0");
  }
}

Eigen::Matrix3d rotate_covariance(const Eigen::Matrix3d& covariance_in_map,
                                  double frame_theta_rad) {
  const double c = std::cos(frame_theta_rad);
  const double s = std::sin(frame_theta_rad);
  Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
  j(0, 0) = c;
  j(0, 1) = s;
  j(1, 0) = -s;
  j(1, 1) = c;
  return j * covariance_in_map * j.transpose();
}

std::vector<std::size_t> LoopCloser::candidates(const PoseGraph& graph,
                                                std::span<const LoopNodeScan> scans,
                                                std::size_t new_node) const {
  std::vector<std::size_t> out;
  if (new_node >= graph.node_count() || scans.size() != graph.node_count()) return out;
  const auto gap = static_cast<std::size_t>(options_.min_node_gap);
  if (new_node < gap) return out;
  const geometry::Pose2D& here = graph.pose(new_node);
  const double chain_here = scans[new_node].chain_distance_m;
  std::vector<std::pair<double, std::size_t>> near;
  for (std::size_t i = 0; i + gap <= new_node; ++i) {
    if (chain_here - scans[i].chain_distance_m < options_.min_chain_distance_m) continue;
    const geometry::Pose2D& there = graph.pose(i);
    const double d = std::hypot(there.x - here.x, there.y - here.y);
    if (d <= options_.search_radius_m) near.emplace_back(d, i);
  }
  std::sort(near.begin(), near.end());
  const auto separation = static_cast<std::size_t>(2 * options_.submap_half_nodes);
  for (const auto& [d, i] : near) {
    if (out.size() >= static_cast<std::size_t>(options_.max_candidates)) break;
    const bool same_visit = std::any_of(out.begin(), out.end(), [&](std::size_t chosen) {
      return (i > chosen ? i - chosen : chosen - i) <= separation;
    });
    if (!same_visit) out.push_back(i);
  }
  return out;
}

std::vector<LoopClosure> LoopCloser::close(const PoseGraph& graph,
                                           std::span<const LoopNodeScan> scans,
                                           std::size_t new_node) const {
  if (new_node >= graph.node_count() || scans.size() != graph.node_count()) {
    throw std::invalid_argument("LoopCloser::close: node out of range or scans/graph mismatch");
  }
  std::vector<LoopClosure> out;
  const std::span<const geometry::Point2D> query = scans[new_node].match_points_in_base;
  if (query.empty()) return out;
  const geometry::Pose2D& estimate = graph.pose(new_node);
  const auto gap = static_cast<std::size_t>(options_.min_node_gap);
  for (const std::size_t candidate : candidates(graph, scans, new_node)) {
    // The candidate's neighbourhood, never reaching into the new node's own chain.
    const std::size_t half = static_cast<std::size_t>(options_.submap_half_nodes);
    const std::size_t first = candidate > half ? candidate - half : 0;
    const std::size_t last = std::min(candidate + half, new_node - gap);
    std::vector<SubmapScan> members;
    for (std::size_t i = first; i <= last; ++i) {
      members.push_back({graph.pose(i), scans[i].map_points_in_base});
    }
    const double reach_m = options_.linear_window_m + 3.0 * options_.submap.sigma_m;
    const Submap submap(members, options_.submap, box_around(query, estimate, reach_m));
    if (submap.field().empty()) continue;
    const CorrelativeScanMatcher matcher(submap.field(), options_.linear_window_m);
    CorrelativeSearchOptions search;
    search.linear_window_m = options_.linear_window_m;
    search.angular_window_rad = options_.angular_window_rad;
    search.min_score = options_.min_score;
    const auto match = matcher.match(query, estimate, search);
    if (!match) continue;
    const double std_xy = std::sqrt(std::max(match->covariance(0, 0), match->covariance(1, 1)));
    if (std_xy > options_.max_position_std_m) continue;
    const RefinedPose refined =
        refine_scan_pose(submap.field(), query, match->pose, options_.refiner);
    const double shift_m =
        std::hypot(refined.pose.x - match->pose.x, refined.pose.y - match->pose.y);
    const double shift_rad = std::abs(geometry::wrap_angle(refined.pose.theta - match->pose.theta));
    if (refined.score < options_.min_score || shift_m > options_.max_refine_shift_m ||
        shift_rad > options_.max_refine_shift_rad) {
      continue;
    }
    const geometry::Pose2D& anchor = graph.pose(candidate);
    LoopClosure closure;
    closure.candidate = candidate;
    closure.score = refined.score;
    closure.edge.from = candidate;
    closure.edge.to = new_node;
    closure.edge.kind = EdgeKind::kLoop;
    closure.edge.relative = geometry::compose(geometry::inverse(anchor), refined.pose);
    const Eigen::Matrix3d covariance =
        options_.covariance_scale * rotate_covariance(match->covariance, anchor.theta);
    closure.edge.information = covariance.inverse();
    closure.edge.information =
        0.5 * (closure.edge.information + closure.edge.information.transpose()).eval();
    out.push_back(closure);
  }
  return out;
}

}  // namespace mobot::slam
