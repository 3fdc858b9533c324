#include "core/slam/correlative_scan_matcher.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "core/slam/scan_points.h"
#include "core/slam/submap.h"
#include "tests/unit/core/slam/synthetic_room.h"

namespace mobot::slam {
namespace {

struct RoomFixture {
  std::vector<testing::Segment> walls = testing::synthetic_room();
  geometry::Pose2D map_pose{4.0, 3.0, 0.3};
  ScanPoints map_scan = scan_to_points(testing::cast_scan(walls, map_pose));
  std::vector<SubmapScan> members{{map_pose, map_scan.points_in_base}};
  Submap submap{members, {}};
};

TEST(CorrelativeScanMatcher, RecoversAKnownOffsetInASyntheticRoom) {
  RoomFixture room;
  const geometry::Pose2D truth{4.3, 2.85, 0.42};
  const ScanPoints query = scan_to_points(testing::cast_scan(room.walls, truth));
  const auto points = voxel_filter(query.points_in_base, 0.05);
  const CorrelativeScanMatcher matcher(room.submap.field(), 0.4);
  CorrelativeSearchOptions options;
  options.linear_window_m = 0.4;
  options.angular_window_rad = 0.3;
  const geometry::Pose2D initial{4.1, 3.05, 0.25};  // 0.2 m, 0.2 m and 10 deg off
  const auto match = matcher.match(points, initial, options);
  ASSERT_TRUE(match.has_value());
  EXPECT_NEAR(match->pose.x, truth.x, 0.05);
  EXPECT_NEAR(match->pose.y, truth.y, 0.05);
  EXPECT_NEAR(match->pose.theta, truth.theta, 0.01);
  EXPECT_GT(match->score, 0.7);
  // The response covariance is positive definite and small for a well-structured room.
  EXPECT_GT(match->covariance.determinant(), 0.0);
  EXPECT_LT(std::sqrt(match->covariance(0, 0)), 0.05);
}

TEST(CorrelativeScanMatcher, BranchAndBoundFindsTheExhaustiveOptimum) {
  RoomFixture room;
  const auto query = voxel_filter(
      scan_to_points(testing::cast_scan(room.walls, {4.2, 3.1, 0.35})).points_in_base, 0.1);
  const CorrelativeScanMatcher matcher(room.submap.field(), 0.3);
  CorrelativeSearchOptions options;
  options.linear_window_m = 0.3;
  options.angular_window_rad = 0.1;
  options.angular_step_rad = 0.02;
  const geometry::Pose2D initial = room.map_pose;
  const auto fast = matcher.match(query, initial, options);
  ASSERT_TRUE(fast.has_value());
  // Exhaustive: every candidate of the same lattice with a one-cell window matcher around it.
  double best = -1.0;
  const double res = room.submap.field().limits().resolution_m;
  for (int k = -5; k <= 5; ++k) {
    for (int dx = -6; dx <= 6; ++dx) {
      for (int dy = -6; dy <= 6; ++dy) {
        CorrelativeSearchOptions single;
        single.linear_window_m = 0.0;
        single.angular_window_rad = 0.0;
        const auto m = matcher.match(
            query, {initial.x + dx * res, initial.y + dy * res, initial.theta + k * 0.02}, single);
        if (m) best = std::max(best, m->score);
      }
    }
  }
  EXPECT_NEAR(fast->score, best, 1e-9);
}

TEST(CorrelativeScanMatcher, NoMatchForNoPointsEmptyGridOrAnUnreachableScore) {
  RoomFixture room;
  const CorrelativeScanMatcher matcher(room.submap.field(), 0.2);
  CorrelativeSearchOptions options;
  EXPECT_FALSE(matcher.match({}, room.map_pose, options).has_value());
  EXPECT_FALSE(
      matcher.match(room.map_scan.points_in_base, {std::nan(""), 0.0, 0.0}, options).has_value());
  options.min_score = 1.01;
  EXPECT_FALSE(matcher.match(room.map_scan.points_in_base, room.map_pose, options).has_value());
  const CorrelativeScanMatcher empty(ProbabilityGrid{}, 0.2);
  EXPECT_FALSE(empty.match(room.map_scan.points_in_base, room.map_pose, {}).has_value());
}

TEST(CorrelativeScanMatcher, RejectsBadOptions) {
  RoomFixture room;
  EXPECT_THROW(CorrelativeScanMatcher(room.submap.field(), -0.1), std::invalid_argument);
  const CorrelativeScanMatcher matcher(room.submap.field(), 0.2);
  CorrelativeSearchOptions options;
  options.linear_window_m = -1.0;
  EXPECT_THROW(matcher.match(room.map_scan.points_in_base, room.map_pose, options),
               std::invalid_argument);
  options = {};
  options.covariance_temperature = 0.0;
  EXPECT_THROW(matcher.match(room.map_scan.points_in_base, room.map_pose, options),
               std::invalid_argument);
  options = {};
  options.angular_window_rad = std::nan("");
  EXPECT_THROW(matcher.match(room.map_scan.points_in_base, room.map_pose, options),
               std::invalid_argument);
}

}  // namespace
}  // namespace mobot::slam
