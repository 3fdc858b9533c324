#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "core/geometry/pose2d.h"

namespace mobot::slam {

enum class EdgeKind {
  kSequential,  // between consecutive nodes, from matching against the local map
  kOdometry,    // between consecutive nodes, the odometry increment
  kLoop,        // from a loop closure; robust kernel in the optimiser
};

// A relative pose constraint: node `to`'s pose expressed in node `from`'s frame is `relative`,
// with the information matrix (inverse covariance) of (x, y, theta) of that relative pose.
struct PoseGraphEdge {
  std::size_t from = 0;
  std::size_t to = 0;
  geometry::Pose2D relative;
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
  EdgeKind kind = EdgeKind::kSequential;
};

// docs/algorithms.md E5: nodes are scan poses in the map frame, edges relative pose constraints.
// The graph only holds; pose_graph_optimizer moves the nodes.
class PoseGraph {
 public:
  // Throws std::invalid_argument on a non-finite pose.
  std::size_t add_node(const geometry::Pose2D& pose_in_map);
  // Throws std::invalid_argument on an index out of range, from == to, a non-finite relative pose
  // or an information matrix that is not finite, symmetric and positive definite.
  void add_edge(const PoseGraphEdge& edge);

  std::size_t node_count() const { return poses_.size(); }
  const std::vector<geometry::Pose2D>& poses() const { return poses_; }
  const geometry::Pose2D& pose(std::size_t node) const { return poses_.at(node); }
  // Throws std::invalid_argument on a size mismatch or non-finite pose.
  void set_poses(std::vector<geometry::Pose2D> poses);
  const std::vector<PoseGraphEdge>& edges() const { return edges_; }

 private:
  std::vector<geometry::Pose2D> poses_;
  std::vector<PoseGraphEdge> edges_;
};

// The residual of an edge at poses a (from) and b (to): relative^-1 (+) (a^-1 (+) b) as (x, y,
// wrapped theta); zero when the poses agree with the constraint.
Eigen::Vector3d edge_residual(const geometry::Pose2D& a, const geometry::Pose2D& b,
                              const geometry::Pose2D& relative);

}  // namespace mobot::slam
