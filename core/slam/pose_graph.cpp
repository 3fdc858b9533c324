#include "core/slam/pose_graph.h"

#include <stdexcept>

#include <Eigen/Cholesky>

namespace mobot::slam {

std::size_t PoseGraph::add_node(const geometry::Pose2D& pose_in_map) {
  if (!geometry::is_finite(pose_in_map)) {
    throw std::invalid_argument("PoseGraph::add_node: non-finite pose");
  }
  poses_.push_back(pose_in_map);
  return poses_.size() - 1;
}

void PoseGraph::add_edge(const PoseGraphEdge& edge) {
  if (edge.from >= poses_.size() || edge.to >= poses_.size() || edge.from == edge.to) {
    throw std::invalid_argument("PoseGraph::add_edge: node index out of range or a self-loop");
  }
  if (!geometry::is_finite(edge.relative) || !edge.information.allFinite() ||
      !edge.information.isApprox(edge.information.transpose(), 1e-9)) {
    throw std::invalid_argument("PoseGraph::add_edge: non-finite or asymmetric constraint");
  }
  const Eigen::LLT<Eigen::Matrix3d> llt(edge.information);
  if (llt.info() != Eigen::Success) {
    throw std::invalid_argument("PoseGraph::add_edge: information not positive definite");
  }
  edges_.push_back(edge);
}

void PoseGraph::set_poses(std::vector<geometry::Pose2D> poses) {
  if (poses.size() != poses_.size()) {
    throw std::invalid_argument("PoseGraph::set_poses: size mismatch");
  }
  for (const auto& p : poses) {
    if (!geometry::is_finite(p)) throw std::invalid_argument("PoseGraph::set_poses: non-finite");
  }
  poses_ = std::move(poses);
}

Eigen::Vector3d edge_residual(const geometry::Pose2D& a, const geometry::Pose2D& b,
                              const geometry::Pose2D& relative) {
  const geometry::Pose2D e =
      geometry::compose(geometry::inverse(relative), geometry::compose(geometry::inverse(a), b));
  return {e.x, e.y, geometry::wrap_angle(e.theta)};
}

}  // namespace mobot::slam
