#include "core/slam/scan_refiner.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "core/slam/scan_points.h"
#include "core/slam/submap.h"
#include "tests/unit/core/slam/synthetic_room.h"

namespace mobot::slam {
namespace {

TEST(ScanRefiner, ConvergesBelowACellFromAnOffsetStart) {
  const auto walls = testing::synthetic_room();
  const geometry::Pose2D truth{5.0, 4.0, -0.2};
  const ScanPoints map_scan = scan_to_points(testing::cast_scan(walls, truth));
  const std::vector<SubmapScan> members{{truth, map_scan.points_in_base}};
  const Submap submap(members, {});
  const auto query =
      voxel_filter(scan_to_points(testing::cast_scan(walls, truth, 181)).points_in_base, 0.05);
  ScanRefinerOptions options;
  options.translation_weight = 0.0;
  options.rotation_weight = 0.0;
  options.max_iterations = 30;
  const RefinedPose refined =
      refine_scan_pose(submap.field(), query, {5.03, 3.97, -0.185}, options);
  // Below a fifth of a cell (the 181-beam query hits the walls elsewhere than the map's beams).
  EXPECT_NEAR(refined.pose.x, truth.x, 0.01);
  EXPECT_NEAR(refined.pose.y, truth.y, 0.01);
  EXPECT_NEAR(refined.pose.theta, truth.theta, 0.006);
  EXPECT_GT(refined.score, 0.9);
  EXPECT_GT(refined.hessian.determinant(), 0.0);
}

TEST(ScanRefiner, StrongPriorsHoldThePoseAtTheStart) {
  const auto walls = testing::synthetic_room();
  const geometry::Pose2D truth{5.0, 4.0, -0.2};
  const ScanPoints scan = scan_to_points(testing::cast_scan(walls, truth));
  const std::vector<SubmapScan> members{{truth, scan.points_in_base}};
  const Submap submap(members, {});
  ScanRefinerOptions options;
  options.translation_weight = 100.0;
  options.rotation_weight = 100.0;
  const geometry::Pose2D start{5.03, 3.97, -0.185};
  const RefinedPose refined = refine_scan_pose(submap.field(), scan.points_in_base, start, options);
  EXPECT_NEAR(refined.pose.x, start.x, 0.002);
  EXPECT_NEAR(refined.pose.theta, start.theta, 0.002);
}

// Two parallel walls and nothing else: the corridor's axis is free. The refinement starts from the
// correlative search's whole-cell answer but is pulled towards the motion prediction along the
// axis, where the field cannot say anything; across it the walls decide.
TEST(ScanRefiner, AlongAFeaturelessCorridorThePoseGoesToThePrior) {
  std::vector<geometry::Point2D> walls_in_map;
  for (double x = -10.0; x <= 10.0; x += 0.02) {
    walls_in_map.push_back({x, -1.0});
    walls_in_map.push_back({x, 1.0});
  }
  const std::vector<SubmapScan> members{{{0.0, 0.0, 0.0}, walls_in_map}};
  const Submap submap(members, {});
  std::vector<geometry::Point2D> scan;
  for (double x = -3.0; x <= 3.0; x += 0.05) {
    scan.push_back({x, -1.0});
    scan.push_back({x, 1.0});
  }
  const geometry::Pose2D truth{0.0, 0.0, 0.0};
  const geometry::Pose2D correlative{0.05, 0.02, 0.0};
  const geometry::Pose2D prediction{0.012, 0.0, 0.0};
  const RefinedPose refined =
      refine_scan_pose(submap.field(), scan, correlative, prediction, ScanRefinerOptions{});
  EXPECT_NEAR(refined.pose.x, prediction.x, 0.005);
  EXPECT_NEAR(refined.pose.y, truth.y, 0.005);
  EXPECT_NEAR(refined.pose.theta, truth.theta, 0.002);
  const RefinedPose without_prior =
      refine_scan_pose(submap.field(), scan, correlative, ScanRefinerOptions{});
  EXPECT_NEAR(without_prior.pose.x, correlative.x, 0.005);
}

TEST(ScanRefiner, ReturnsTheStartForNothingToMatchAndRejectsBadOptions) {
  const geometry::Pose2D start{1.0, 2.0, 0.5};
  const RefinedPose empty = refine_scan_pose(ProbabilityGrid{}, {}, start);
  EXPECT_EQ(empty.pose, start);
  EXPECT_DOUBLE_EQ(empty.score, 0.0);
  const std::vector<geometry::Point2D> points{{1.0, 0.0}};
  const geometry::Pose2D bad{std::nan(""), 0.0, 0.0};
  EXPECT_TRUE(std::isnan(refine_scan_pose(ProbabilityGrid{}, points, bad).pose.x));
  ScanRefinerOptions options;
  options.max_iterations = -1;
  EXPECT_THROW(refine_scan_pose(ProbabilityGrid{}, points, start, options), std::invalid_argument);
  options = {};
  options.translation_weight = std::nan("");
  EXPECT_THROW(refine_scan_pose(ProbabilityGrid{}, points, start, options), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::slam
