#include "core/slam/loop_closer.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "core/slam/scan_points.h"
#include "tests/unit/core/slam/synthetic_room.h"

namespace mobot::slam {
namespace {

// Nodes 0..4 near (3, 2), nodes 5..39 on a walk away along the room and back, node 40 (the new
// one) near the start again.
struct LoopFixture {
  std::vector<testing::Segment> walls = testing::synthetic_room();
  std::vector<geometry::Pose2D> truth;
  std::vector<ScanPoints> scans;
  std::vector<std::vector<geometry::Point2D>> match_points;
  PoseGraph graph;

  explicit LoopFixture(const std::vector<testing::Segment>& new_node_world,
                       geometry::Pose2D new_node_error) {
    for (int i = 0; i < 5; ++i) truth.push_back({2.8 + 0.1 * i, 2.0, 0.1 * i});
    for (int i = 0; i < 35; ++i)
      truth.push_back({3.0 + 0.15 * (i % 18), 5.0 + 1.5 * (i / 18), 1.0});
    truth.push_back({3.1, 2.1, 0.25});
    for (std::size_t i = 0; i < truth.size(); ++i) {
      const auto& world = i + 1 == truth.size() ? new_node_world : walls;
      scans.push_back(scan_to_points(testing::cast_scan(world, truth[i], 181, std::numbers::pi)));
      match_points.push_back(voxel_filter(scans.back().points_in_base, 0.05));
      graph.add_node(i + 1 == truth.size() ? geometry::compose(truth[i], new_node_error)
                                           : truth[i]);
    }
  }

  std::vector<LoopNodeScan> node_scans() const {
    std::vector<LoopNodeScan> out;
    for (std::size_t i = 0; i < scans.size(); ++i) {
      out.push_back({match_points[i], scans[i].points_in_base, 1.0 * static_cast<double>(i)});
    }
    return out;
  }
};

TEST(LoopCloser, ClosesARevisitWithTheTrueRelativePose) {
  const LoopFixture f(testing::synthetic_room(), {0.25, -0.2, 0.08});
  const LoopCloser closer;
  const auto scans = f.node_scans();
  const std::size_t new_node = f.truth.size() - 1;
  const auto candidates = closer.candidates(f.graph, scans, new_node);
  ASSERT_FALSE(candidates.empty());
  EXPECT_LT(candidates[0], 5U);
  const auto closures = closer.close(f.graph, scans, new_node);
  ASSERT_FALSE(closures.empty());
  const PoseGraphEdge& edge = closures[0].edge;
  EXPECT_EQ(edge.kind, EdgeKind::kLoop);
  EXPECT_EQ(edge.to, new_node);
  const geometry::Pose2D expected =
      geometry::compose(geometry::inverse(f.truth[edge.from]), f.truth[new_node]);
  EXPECT_NEAR(edge.relative.x, expected.x, 0.03);
  EXPECT_NEAR(edge.relative.y, expected.y, 0.03);
  EXPECT_NEAR(edge.relative.theta, expected.theta, 0.01);
  EXPECT_GT(edge.information.determinant(), 0.0);
}

TEST(LoopCloser, RejectsAWrongMatch) {
  // The new node's scan comes from another place altogether (an empty 5 x 3 m room), while the
  // graph believes it is back at the start.
  const std::vector<testing::Segment> elsewhere = {
      {{0, 0}, {5, 0}}, {{5, 0}, {5, 3}}, {{5, 3}, {0, 3}}, {{0, 3}, {0, 0}}};
  LoopFixture f(elsewhere, {});
  f.truth.back() = {1.0, 1.0, 0.25};
  f.scans.back() =
      scan_to_points(testing::cast_scan(elsewhere, f.truth.back(), 181, std::numbers::pi));
  f.match_points.back() = voxel_filter(f.scans.back().points_in_base, 0.05);
  const LoopCloser closer;
  const auto scans = f.node_scans();
  ASSERT_FALSE(closer.candidates(f.graph, scans, f.truth.size() - 1).empty());
  EXPECT_TRUE(closer.close(f.graph, scans, f.truth.size() - 1).empty());
}

TEST(LoopCloser, IgnoresTheRecentChainAndBoundsTheCandidates) {
  const LoopFixture f(testing::synthetic_room(), {});
  LoopCloserOptions options;
  options.min_node_gap = 41;  // every older node is "recent"
  auto scans = f.node_scans();
  EXPECT_TRUE(LoopCloser(options).candidates(f.graph, scans, 40).empty());
  options = {};
  options.max_candidates = 0;
  EXPECT_TRUE(LoopCloser(options).close(f.graph, scans, 40).empty());
  options = {};
  options.min_chain_distance_m = 1000.0;
  EXPECT_TRUE(LoopCloser(options).candidates(f.graph, scans, 40).empty());
  EXPECT_THROW(LoopCloser().close(f.graph, scans, 41), std::invalid_argument);
  scans.pop_back();
  EXPECT_THROW(LoopCloser().close(f.graph, scans, 40), std::invalid_argument);
}

TEST(LoopCloser, RejectsBadOptions) {
  LoopCloserOptions options;
  options.min_node_gap = 0;
  EXPECT_THROW(LoopCloser{options}, std::invalid_argument);
  options = {};
  options.search_radius_m = std::nan("");
  EXPECT_THROW(LoopCloser{options}, std::invalid_argument);
  options = {};
  options.covariance_scale = 0.0;
  EXPECT_THROW(LoopCloser{options}, std::invalid_argument);
}

TEST(RotateCovariance, TurnsTheTranslationBlockIntoTheNodeFrame) {
  Eigen::Matrix3d covariance = Eigen::Vector3d(4.0, 1.0, 0.5).asDiagonal();
  const Eigen::Matrix3d rotated = rotate_covariance(covariance, std::numbers::pi / 2.0);
  EXPECT_NEAR(rotated(0, 0), 1.0, 1e-12);
  EXPECT_NEAR(rotated(1, 1), 4.0, 1e-12);
  EXPECT_NEAR(rotated(2, 2), 0.5, 1e-12);
}

}  // namespace
}  // namespace mobot::slam
