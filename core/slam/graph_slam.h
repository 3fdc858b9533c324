#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "core/geometry/pose2d.h"
#include "core/mapping/occupancy_grid.h"
#include "core/msgs/laser_scan.h"
#include "core/slam/map_renderer.h"

namespace mobot::slam {

// docs/algorithms.md E5. Every parameter of the graph SLAM with its default; the defaults are the
// ones the Intel benchmark (tests/bench/slam_intel.sh) is measured with, unchanged per log.
struct GraphSlamOptions {
  // --- scans ---
  // E5: gmapping's maxUrange on the Dashgo; farther returns are sparse and angularly noisy.
  double max_range_m = 8.0;
  // Matching uses one point per voxel of this size: beams bunch up on near walls, which would
  // otherwise outweigh the far geometry that fixes the pose.
  double voxel_size_m = 0.05;

  // --- nodes ---
  // A scan becomes a graph node once the base moved this far or turned this much since the last
  // node: gmapping's linearUpdate 0.05 m / angularUpdate 2.5 deg of the Dashgo thesis. Smaller
  // motions are still matched and tracked as an offset from the last node, so a robot standing
  // still does not grow the graph.
  double min_travel_m = 0.05;
  double min_rotation_rad = 0.0436;  // 2.5 deg

  // --- grids ---
  // E5: 0.05 m cells, the map resolution of the Dashgo thesis.
  double resolution_m = 0.05;
  // Std-dev of the Gaussian each scan point is smeared with in the matching field (Karto's
  // smear): wide enough for a smooth Gauss-Newton basin, narrow enough to keep walls apart.
  double match_field_sigma_m = 0.07;

  // --- scan to local map ---
  // The local map is the scans of up to this many most recent nodes ...
  int local_map_nodes = 25;
  // ... that lie within this travelled distance of the newest (slam_toolbox's scan buffer 10 m).
  double local_map_chain_distance_m = 10.0;
  // ... and lie at least this far apart along the chain (0: every node). Spacing them out makes
  // the local map span metres of travel instead of the last few node steps, so heading and
  // position are matched against geometry placed before the recent drift. The newest node and
  // the first (the map's anchor) are members whatever their spacing.
  double local_map_spacing_m = 0.0;
  // Search window of the real-time correlative matcher around the odometry prediction.
  // Cartographer's real-time window is 0.1 m / 20 deg; odometry with 3 % step noise and a 1 m step
  // needs +-0.1 m (3 sigma), so twice that.
  double local_search_linear_m = 0.25;
  double local_search_angular_rad = 0.26;  // 15 deg
  // Angular step of the search; the matcher refines it further (Gauss-Newton), so 0.5 deg is
  // enough at 8 m (4 cm at the end of the beam).
  double angular_step_rad = 0.0087;
  // A match scoring below this (mean field value of the points, 0..1) is not trusted: the node is
  // chained by odometry with odometry's covariance instead.
  double local_min_score = 0.35;

  // --- refinement (Gauss-Newton on the bicubic field) ---
  int refine_max_iterations = 15;
  // Pull towards the correlative estimate, per point (Cartographer's translation/rotation
  // weights): keeps the refinement from sliding along a corridor.
  double refine_translation_weight = 0.1;
  double refine_rotation_weight = 0.1;

  // --- odometry ---
  // Every node is tied to the previous one twice: by the match and by the odometry increment, each
  // with its covariance, so the optimiser (and the node's first estimate) weighs the two. Std-dev
  // of the increment per metre travelled and per radian turned, plus heading drift per metre, with
  // floors (for wheel odometry whose scale is calibrated to ~1-3 %).
  double odom_translation_sigma_per_m = 0.03;
  double odom_rotation_sigma_per_rad = 0.03;
  double odom_rotation_sigma_per_m = 0.01;
  double odom_min_sigma_m = 0.01;
  double odom_min_sigma_rad = 0.005;

  // --- loop closure ---
  // Older nodes within this distance of the new node's pose are candidates ...
  double loop_search_radius_m = 4.0;
  // ... unless they are among the new node's chain: fewer than this many nodes back or within
  // this travelled distance (they are already tied to it by the local map).
  int loop_min_node_gap = 30;
  double loop_min_chain_distance_m = 8.0;
  // The candidate's submap: nodes within this many indices of it on both sides.
  int loop_submap_half_nodes = 12;
  // Search window around the predicted relative pose: the drift accumulated since the candidate.
  double loop_search_linear_m = 2.0;
  double loop_search_angular_rad = 0.35;  // 20 deg
  // A closure needs at least this score (mean field value, 0..1); Karto's fine response 0.45,
  // Cartographer's global 0.6.
  double loop_min_score = 0.55;
  // Bounded work per node: at most this many candidate submaps are matched; attempts are made
  // only on every n-th node (every 2nd node closes ~450 loops on Intel for no better ATE than
  // every 3rd, at 1.5 x the time).
  int max_loop_candidates_per_node = 2;
  // The response covariance is optimistic (neighbouring beams are not independent, and closures on
  // consecutive nodes share one submap): loop edges get it times this factor, sequential match
  // edges times match_covariance_scale. 16 measured best of 1/4/16/50 on the Intel benchmark.
  double loop_covariance_scale = 16.0;
  double match_covariance_scale = 1.0;
  int loop_attempt_every_n_nodes = 3;

  // --- optimisation ---
  // After a closure, and otherwise every this many nodes (0: only after closures).
  int optimize_every_n_nodes = 0;
  int optimizer_max_iterations = 20;
  // Huber kernel on loop edges, in sigmas of the Mahalanobis residual: one wrong closure pulls with
  // a constant force instead of a quadratic one.
  double loop_huber_delta = 2.0;
};

struct SlamStats {
  std::size_t scans = 0, nodes = 0, loop_closures = 0;
};

class GraphSlamState;

// docs/algorithms.md E5: 2D graph SLAM in the style of Karto / slam_toolbox / Cartographer 2D.
// Scans are matched against a local map of recent nodes (correlative search + Gauss-Newton), nodes
// are linked by relative pose constraints, loops are closed against submaps of older nodes and the
// graph is optimised with sparse Levenberg-Marquardt. Single-threaded and deterministic: every
// computation happens inside add_scan.
class GraphSlam {
 public:
  // Throws std::invalid_argument on bad options (non-positive sizes or counts, non-finite values).
  explicit GraphSlam(const GraphSlamOptions& options = {});
  ~GraphSlam();
  GraphSlam(GraphSlam&&) noexcept;
  GraphSlam& operator=(GraphSlam&&) noexcept;
  GraphSlam(const GraphSlam&) = delete;
  GraphSlam& operator=(const GraphSlam&) = delete;

  const GraphSlamOptions& options() const { return options_; }

  // One scan with the odometry pose of the base at the scan's time (any odometry frame, only
  // increments are used). The first scan anchors the map frame at the start pose (set_start_pose,
  // default the first odometry pose). A scan becomes a node when the robot moved >= min_travel_m
  // or turned >= min_rotation_rad since the last node; otherwise only the pose is tracked.
  // Returns the corrected pose of the base in the map frame for this scan. Throws
  // std::invalid_argument on a non-finite odometry pose; a scan without usable returns is tracked
  // by odometry alone.
  geometry::Pose2D add_scan(const msgs::LaserScan& scan, const geometry::Pose2D& odom_pose);
  // Before the first scan: where the first scan's base pose lies in the map frame. Ignored after.
  void set_start_pose(const geometry::Pose2D& start_pose_in_map);

  // Latest corrected base pose (map frame); the start pose before any scan.
  geometry::Pose2D pose() const;
  // The map -> odom correction: map pose = compose(map_from_odom(), odom pose).
  geometry::Pose2D map_from_odom() const;
  // The optimised poses of the graph's nodes, in node order.
  std::vector<geometry::Pose2D> node_poses() const;
  // The optimised pose of every scan added, in input order: a node's own pose, or for a tracked
  // scan its node's optimised pose composed with the scan's matched offset from it.
  std::vector<geometry::Pose2D> scan_poses() const;
  SlamStats stats() const;

  // The occupancy grid from the optimised poses (origin aligned to options.align_m).
  mapping::OccupancyGrid render_map(const MapRenderOptions& options = {}) const;

 private:
  GraphSlamOptions options_;
  std::unique_ptr<GraphSlamState> state_;
};

}  // namespace mobot::slam
