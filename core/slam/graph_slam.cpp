#include "core/slam/graph_slam.h"

#include <cmath>
#include <stdexcept>

namespace mobot::slam {

// The first version tracks odometry only; matching, the graph and loop closure follow.
class GraphSlamState {
 public:
  bool started = false;
  geometry::Pose2D start_pose;
  bool start_pose_set = false;
  geometry::Pose2D map_from_odom;
  geometry::Pose2D pose;
  std::vector<geometry::Pose2D> scan_poses;
  std::vector<ScanPoints> scans;
  SlamStats stats;
};

namespace {

void check_options(const GraphSlamOptions& o) {
  const double values[] = {o.max_range_m,      o.voxel_size_m, o.min_travel_m,
                           o.min_rotation_rad, o.resolution_m, o.match_field_sigma_m};
  for (double v : values) {
    if (!std::isfinite(v) || v < 0.0) {
      throw std::invalid_argument("GraphSlamOptions: values must be finite and non-negative");
    }
  }
  if (o.max_range_m <= 0.0 || o.resolution_m <= 0.0 || o.match_field_sigma_m <= 0.0) {
    throw std::invalid_argument("GraphSlamOptions: max_range_m, resolution_m, sigma must be > 0");
  }
}

}  // namespace

GraphSlam::GraphSlam(const GraphSlamOptions& options)
    : options_(options), state_(std::make_unique<GraphSlamState>()) {
  check_options(options_);
}

GraphSlam::~GraphSlam() = default;
GraphSlam::GraphSlam(GraphSlam&&) noexcept = default;
GraphSlam& GraphSlam::operator=(GraphSlam&&) noexcept = default;

void GraphSlam::set_start_pose(const geometry::Pose2D& start_pose_in_map) {
  if (state_->started) return;
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
  if (!s.started) {
    s.started = true;
    const geometry::Pose2D start = s.start_pose_set ? s.start_pose : odom_pose;
    s.map_from_odom = geometry::compose(start, geometry::inverse(odom_pose));
  }
  s.pose = geometry::compose(s.map_from_odom, odom_pose);
  s.scan_poses.push_back(s.pose);
  s.scans.push_back(scan_to_points(scan, {options_.max_range_m, 0.05, 0.0}));
  ++s.stats.scans;
  s.stats.nodes = s.scans.size();
  return s.pose;
}

geometry::Pose2D GraphSlam::pose() const { return state_->pose; }
geometry::Pose2D GraphSlam::map_from_odom() const { return state_->map_from_odom; }
std::vector<geometry::Pose2D> GraphSlam::node_poses() const { return state_->scan_poses; }
std::vector<geometry::Pose2D> GraphSlam::scan_poses() const { return state_->scan_poses; }
SlamStats GraphSlam::stats() const { return state_->stats; }

mapping::OccupancyGrid GraphSlam::render_map(const MapRenderOptions& options) const {
  std::vector<PosedScan> posed;
  posed.reserve(state_->scans.size());
  for (std::size_t i = 0; i < state_->scans.size(); ++i) {
    posed.push_back({state_->scan_poses[i], &state_->scans[i]});
  }
  return render_occupancy_grid(posed, options);
}

}  // namespace mobot::slam
