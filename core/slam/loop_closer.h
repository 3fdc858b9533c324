#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "core/geometry/pose2d.h"
#include "core/slam/pose_graph.h"
#include "core/slam/scan_refiner.h"
#include "core/slam/submap.h"

namespace mobot::slam {

struct LoopCloserOptions {
  // Older nodes within this distance of the new node's current estimate are candidates ...
  double search_radius_m = 4.0;
  // ... unless they belong to the new node's own chain: fewer than this many nodes back, or less
  // than this travelled distance back (the local map already ties them to the new node).
  int min_node_gap = 30;
  double min_chain_distance_m = 8.0;
  // A candidate's submap holds the nodes within this many indices of it (Karto's "chain").
  int submap_half_nodes = 12;
  // The search window around the new node's current estimate: the drift since the candidate.
  double linear_window_m = 2.0;
  double angular_window_rad = 0.35;
  // Accept only a match whose correlative and refined scores (mean field value) reach this.
  double min_score = 0.55;
  // At most this many candidate submaps per new node (bounds add_scan's worst case); candidates
  // closer than 2 * submap_half_nodes indices to a chosen one are the same visit and skipped.
  int max_candidates = 2;
  // Consistency: the refinement must stay within this of the correlative optimum (a refinement
  // that slides far found a different basin than the search), and the response's position
  // std-dev must stay below max_position_std_m (an ambiguous, corridor-like response is no loop).
  double max_refine_shift_m = 0.1;
  double max_refine_shift_rad = 0.05;
  double max_position_std_m = 0.08;
  // The response covariance is optimistic (neighbouring beams are not independent); loop edges
  // get it times this factor.
  double covariance_scale = 4.0;
  SubmapOptions submap;
  ScanRefinerOptions refiner;
};

// One node's scan as the loop closer needs it: a sparse point set to match with and the full one
// to build submaps from, plus the distance the robot had travelled at that node.
struct LoopNodeScan {
  std::span<const geometry::Point2D> match_points_in_base;
  std::span<const geometry::Point2D> map_points_in_base;
  double chain_distance_m = 0.0;
};

struct LoopClosure {
  PoseGraphEdge edge;  // from the candidate to the new node, kind kLoop
  double score = 0.0;
  std::size_t candidate = 0;
};

// docs/algorithms.md E5 (Karto's MapperGraph::TryCloseLoop with Cartographer's branch and bound):
// for a new node, candidates among older nodes near it but off its recent chain; the new scan is
// matched with a wide window against a submap of each candidate's neighbourhood; a match that is
// good (score), unambiguous (response spread) and self-consistent (refinement stays put) becomes a
// loop edge.
class LoopCloser {
 public:
  // Throws std::invalid_argument on negative, non-finite or zero-count options.
  explicit LoopCloser(const LoopCloserOptions& options = {});
  const LoopCloserOptions& options() const { return options_; }

  // The candidates `new_node` would be matched against, best (closest) first, at most
  // max_candidates. `scans` has one entry per graph node.
  std::vector<std::size_t> candidates(const PoseGraph& graph, std::span<const LoopNodeScan> scans,
                                      std::size_t new_node) const;
  // The accepted closures for `new_node` (none when no candidate passes). Throws
  // std::invalid_argument when `scans` and the graph disagree in size or new_node is out of range.
  std::vector<LoopClosure> close(const PoseGraph& graph, std::span<const LoopNodeScan> scans,
                                 std::size_t new_node) const;

 private:
  LoopCloserOptions options_;
};

// A covariance of a pose's (x, y, theta) in the map frame, expressed in a frame rotated by
// `frame_theta_rad` (what a relative edge from a node with that heading needs).
Eigen::Matrix3d rotate_covariance(const Eigen::Matrix3d& covariance_in_map, double frame_theta_rad);

}  // namespace mobot::slam
