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
