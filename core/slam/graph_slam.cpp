#include "core/slam/graph_slam.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "core/slam/correlative_scan_matcher.h"
#include "core/slam/loop_closer.h"
#include "core/slam/pose_graph.h"
#include "core/slam/pose_graph_optimizer.h"
#include "core/slam/scan_points.h"
#include "core/slam/scan_refiner.h"
#include "core/slam/submap.h"

namespace mobot::slam {

namespace {

void check_options(const GraphSlamOptions& o) {
  const double values[] = {o.max_range_m,
                           o.voxel_size_m,
                           o.min_travel_m,
                           o.min_rotation_rad,
                           o.resolution_m,
                           o.match_field_sigma_m,
                           o.local_map_chain_distance_m,
                           o.local_map_spacing_m,
                           o.local_search_linear_m,
                           o.local_search_angular_rad,
                           o.angular_step_rad,
                           o.local_min_score,
                           o.refine_translation_weight,
                           o.refine_rotation_weight,
                           o.odom_translation_sigma_per_m,
                           o.odom_rotation_sigma_per_rad,
                           o.odom_rotation_sigma_per_m,
                           o.odom_min_sigma_m,
                           o.odom_min_sigma_rad,
                           o.loop_search_radius_m,
                           o.loop_min_chain_distance_m,
                           o.loop_search_linear_m,
                           o.loop_search_angular_rad,
                           o.loop_min_score,
                           o.loop_huber_delta,
                           o.loop_covariance_scale,
                           o.match_covariance_scale};
  for (double v : values) {
    if (!std::isfinite(v) || v < 0.0) {
      throw std::invalid_argument("GraphSlamOptions: every value must be finite and >= 0");
    }
  }
  if (!(o.max_range_m > 0.0) || !(o.resolution_m > 0.0) || !(o.match_field_sigma_m > 0.0) ||
      !(o.odom_min_sigma_m > 0.0) || !(o.odom_min_sigma_rad > 0.0) ||
      !(o.loop_covariance_scale > 0.0) || !(o.match_covariance_scale > 0.0)) {
    throw std::invalid_argument(
        "GraphSlamOptions: max_range_m, resolution_m, match_field_sigma_m and the odometry "
        "sigma floors must be > 0");
  }
  if (o.local_map_nodes < 1 || o.refine_max_iterations < 0 || o.loop_min_node_gap < 1 ||
      o.loop_submap_half_nodes < 0 || o.max_loop_candidates_per_node < 0 ||
      o.loop_attempt_every_n_nodes < 1 || o.optimize_every_n_nodes < 0 ||
      o.optimizer_max_iterations < 0) {
    throw std::invalid_argument("GraphSlamOptions: node counts out of range");
  }
}

Eigen::Matrix3d diagonal_covariance(double sigma_xy, double sigma_theta) {
  return Eigen::Vector3d(sigma_xy * sigma_xy, sigma_xy * sigma_xy, sigma_theta * sigma_theta)
      .asDiagonal();
}

Eigen::Matrix3d symmetric_inverse(const Eigen::Matrix3d& covariance) {
  const Eigen::Matrix3d information = covariance.inverse();
  return 0.5 * (information + information.transpose());
}

}  // namespace

struct NodeScan {
  ScanPoints scan;                              // every return (maps, submaps)
  std::vector<geometry::Point2D> match_points;  // voxel-filtered (matching)
  double chain_distance_m = 0.0;
};

// Where a scan's optimised pose comes from: its node's pose composed with this offset.
struct ScanRecord {
  std::size_t node = 0;
  geometry::Pose2D offset_from_node;
};

class GraphSlamState {
 public:
  bool started = false;
  bool start_pose_set = false;
  geometry::Pose2D start_pose;
  geometry::Pose2D pose;  // latest corrected base pose
  geometry::Pose2D last_odom;
  geometry::Pose2D map_from_odom;
  geometry::Pose2D odom_since_node;  // odometry increment since the last node
  PoseGraph graph;
  std::vector<NodeScan> nodes;
  std::vector<ScanRecord> scans;
  SlamStats stats;
  std::size_t nodes_since_optimization = 0;
};

GraphSlam::GraphSlam(const GraphSlamOptions& options)
    : options_(options), state_(std::make_unique<GraphSlamState>()) {
  check_options(options_);
}

GraphSlam::~GraphSlam() = default;
GraphSlam::GraphSlam(GraphSlam&&) noexcept = default;
GraphSlam& GraphSlam::operator=(GraphSlam&&) noexcept = default;

void GraphSlam::set_start_pose(const geometry::Pose2D& start_pose_in_map) {
  if (state_->started) return;
  if (!geometry::is_finite(start_pose_in_map)) {
    throw std::invalid_argument("GraphSlam::set_start_pose: non-finite pose");
  }
  state_->start_pose = start_pose_in_map;
  state_->start_pose_set = true;
  state_->pose = start_pose_in_map;
}

geometry::Pose2D GraphSlam::add_scan(const msgs::LaserScan& scan,
                                     const geometry::Pose2D& odom_pose) {
  if (!geometry::is_finite(odom_pose)) {
    throw std::invalid_argument("GraphSlam::add_scan: non-finite odometry pose");
  }
  GraphSlamState& s = *state_;
  const GraphSlamOptions& o = options_;
  ScanPointsOptions points_options;
  points_options.max_range_m = o.max_range_m;
  NodeScan current;
  current.scan = scan_to_points(scan, points_options);
  current.match_points = voxel_filter(current.scan.points_in_base, o.voxel_size_m);
  ++s.stats.scans;

  if (!s.started) {
    s.started = true;
    s.pose = s.start_pose_set ? s.start_pose : odom_pose;
    s.last_odom = odom_pose;
    s.map_from_odom = geometry::compose(s.pose, geometry::inverse(odom_pose));
    s.graph.add_node(s.pose);
    s.nodes.push_back(std::move(current));
    s.scans.push_back({0, {}});
    s.stats.nodes = 1;
    return s.pose;
  }

  const geometry::Pose2D odom_step = geometry::compose(geometry::inverse(s.last_odom), odom_pose);
  s.last_odom = odom_pose;
  s.odom_since_node = geometry::compose(s.odom_since_node, odom_step);
  const geometry::Pose2D predicted = geometry::compose(s.pose, odom_step);

  // Scan to local map: the recent chain's scans at their current (optimised) poses.
  geometry::Pose2D corrected = predicted;
  std::optional<Eigen::Matrix3d> match_covariance;
  if (!current.match_points.empty()) {
    std::vector<SubmapScan> members;
    const double newest_chain = s.nodes.back().chain_distance_m;
    double last_member_chain = newest_chain + 2.0 * o.local_map_spacing_m;
    for (std::size_t node = s.nodes.size(); node-- > 0 &&
                                            members.size() <
                                                static_cast<std::size_t>(o.local_map_nodes);) {
      const double chain = s.nodes[node].chain_distance_m;
      if (newest_chain - chain > o.local_map_chain_distance_m) break;
      // The first node stays while it is within reach: with it skipped, the scans of the first
      // spacing's length would be matched against the newest node alone, chained node to node, and
      // the map is drawn for good at the heading that chain drifts to (the office tour's worst
      // error 0.115 m at a corridor's end, from 0.006 rad after its first metre).
      if (last_member_chain - chain < o.local_map_spacing_m && node != 0) continue;
      last_member_chain = chain;
      members.push_back({s.graph.pose(node), s.nodes[node].scan.points_in_base});
    }
    SubmapOptions submap_options{o.resolution_m, o.match_field_sigma_m};
    const double reach_m = o.local_search_linear_m + 3.0 * o.match_field_sigma_m;
    const Submap local(members, submap_options,
                       box_around(current.match_points, predicted, reach_m));
    if (!local.field().empty()) {
      const CorrelativeScanMatcher matcher(local.field(), o.local_search_linear_m);
      CorrelativeSearchOptions search;
      search.linear_window_m = o.local_search_linear_m;
      search.angular_window_rad = o.local_search_angular_rad;
      search.angular_step_rad = o.angular_step_rad;
      search.min_score = o.local_min_score;
      const auto match = matcher.match(current.match_points, predicted, search);
      if (match) {
        ScanRefinerOptions refine;
        refine.max_iterations = o.refine_max_iterations;
        refine.translation_weight = o.refine_translation_weight;
        refine.rotation_weight = o.refine_rotation_weight;
        const RefinedPose refined =
            refine_scan_pose(local.field(), current.match_points, match->pose, predicted, refine);
        if (refined.score >= o.local_min_score) {
          corrected = refined.pose;
          match_covariance = match->covariance;
        }
      }
    }
  }
  s.pose = corrected;

  const std::size_t last_node = s.nodes.size() - 1;
  const geometry::Pose2D& last_node_pose = s.graph.pose(last_node);
  const geometry::Pose2D from_node =
      geometry::compose(geometry::inverse(last_node_pose), corrected);
  const double travel_m = std::hypot(from_node.x, from_node.y);
  const bool is_node =
      !current.scan.points_in_base.empty() &&
      (travel_m >= o.min_travel_m || std::abs(from_node.theta) >= o.min_rotation_rad);
  if (!is_node) {
    s.scans.push_back({last_node, from_node});
    s.map_from_odom = geometry::compose(s.pose, geometry::inverse(odom_pose));
    return s.pose;
  }

  // A new node, chained to the previous one by the match and by odometry; its first estimate is
  // the information-weighted mean of the two (what optimising this pair alone would give).
  const double odom_m = std::hypot(s.odom_since_node.x, s.odom_since_node.y);
  const double odom_rad = std::abs(s.odom_since_node.theta);
  const Eigen::Matrix3d odom_information = symmetric_inverse(diagonal_covariance(
      std::max(o.odom_min_sigma_m, o.odom_translation_sigma_per_m * odom_m),
      std::max(o.odom_min_sigma_rad,
               o.odom_rotation_sigma_per_rad * odom_rad + o.odom_rotation_sigma_per_m * odom_m)));
  geometry::Pose2D relative = s.odom_since_node;
  std::optional<PoseGraphEdge> match_edge;
  if (match_covariance) {
    PoseGraphEdge edge;
    edge.from = last_node;
    edge.relative = from_node;
    edge.kind = EdgeKind::kSequential;
    edge.information = symmetric_inverse(
        o.match_covariance_scale * rotate_covariance(*match_covariance, last_node_pose.theta));
    match_edge = edge;
    const Eigen::Vector3d odom(s.odom_since_node.x, s.odom_since_node.y, s.odom_since_node.theta);
    const Eigen::Vector3d matched(
        from_node.x, from_node.y,
        s.odom_since_node.theta + geometry::wrap_angle(from_node.theta - s.odom_since_node.theta));
    const Eigen::Vector3d fused = (edge.information + odom_information)
                                      .ldlt()
                                      .solve(edge.information * matched + odom_information * odom);
    relative = {fused.x(), fused.y(), geometry::wrap_angle(fused.z())};
  }
  corrected = geometry::compose(last_node_pose, relative);
  s.pose = corrected;
  PoseGraphEdge odom_edge;
  odom_edge.from = last_node;
  odom_edge.relative = s.odom_since_node;
  odom_edge.information = odom_information;
  odom_edge.kind = EdgeKind::kOdometry;
  current.chain_distance_m = s.nodes.back().chain_distance_m + travel_m;
  const std::size_t node = s.graph.add_node(corrected);
  odom_edge.to = node;
  s.graph.add_edge(odom_edge);
  if (match_edge) {
    match_edge->to = node;
    s.graph.add_edge(*match_edge);
  }
  s.nodes.push_back(std::move(current));
  s.scans.push_back({node, {}});
  s.odom_since_node = {};
  s.stats.nodes = s.nodes.size();
  ++s.nodes_since_optimization;

  bool optimize = o.optimize_every_n_nodes > 0 &&
                  s.nodes_since_optimization >= static_cast<std::size_t>(o.optimize_every_n_nodes);
  if (o.max_loop_candidates_per_node > 0 &&
      node % static_cast<std::size_t>(o.loop_attempt_every_n_nodes) == 0) {
    LoopCloserOptions loop;
    loop.search_radius_m = o.loop_search_radius_m;
    loop.min_node_gap = o.loop_min_node_gap;
    loop.min_chain_distance_m = o.loop_min_chain_distance_m;
    loop.submap_half_nodes = o.loop_submap_half_nodes;
    loop.linear_window_m = o.loop_search_linear_m;
    loop.angular_window_rad = o.loop_search_angular_rad;
    loop.min_score = o.loop_min_score;
    loop.max_candidates = o.max_loop_candidates_per_node;
    loop.covariance_scale = o.loop_covariance_scale;
    loop.submap = {o.resolution_m, o.match_field_sigma_m};
    loop.refiner.max_iterations = o.refine_max_iterations;
    loop.refiner.translation_weight = o.refine_translation_weight;
    loop.refiner.rotation_weight = o.refine_rotation_weight;
    std::vector<LoopNodeScan> scans;
    scans.reserve(s.nodes.size());
    for (const NodeScan& n : s.nodes) {
      scans.push_back({n.match_points, n.scan.points_in_base, n.chain_distance_m});
    }
    const std::vector<LoopClosure> closures = LoopCloser(loop).close(s.graph, scans, node);
    for (const LoopClosure& closure : closures) s.graph.add_edge(closure.edge);
    s.stats.loop_closures += closures.size();
    optimize = optimize || !closures.empty();
  }
  if (optimize) {
    PoseGraphOptimizerOptions optimizer;
    optimizer.max_iterations = o.optimizer_max_iterations;
    optimizer.loop_huber_delta = o.loop_huber_delta;
    optimize_pose_graph(s.graph, optimizer);
    s.nodes_since_optimization = 0;
    s.pose = s.graph.pose(node);
  }
  s.map_from_odom = geometry::compose(s.pose, geometry::inverse(odom_pose));
  return s.pose;
}

geometry::Pose2D GraphSlam::pose() const { return state_->pose; }
geometry::Pose2D GraphSlam::map_from_odom() const { return state_->map_from_odom; }
std::vector<geometry::Pose2D> GraphSlam::node_poses() const { return state_->graph.poses(); }

std::vector<geometry::Pose2D> GraphSlam::scan_poses() const {
  std::vector<geometry::Pose2D> out;
  out.reserve(state_->scans.size());
  for (const ScanRecord& record : state_->scans) {
    out.push_back(geometry::compose(state_->graph.pose(record.node), record.offset_from_node));
  }
  return out;
}

SlamStats GraphSlam::stats() const { return state_->stats; }

mapping::OccupancyGrid GraphSlam::render_map(const MapRenderOptions& options) const {
  std::vector<PosedScan> posed;
  posed.reserve(state_->nodes.size());
  for (std::size_t i = 0; i < state_->nodes.size(); ++i) {
    posed.push_back({state_->graph.pose(i), &state_->nodes[i].scan});
  }
  return render_occupancy_grid(posed, options);
}

}  // namespace mobot::slam
