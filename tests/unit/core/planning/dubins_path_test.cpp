#include "core/planning/dubins_path.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace mobot::planning {
namespace {

constexpr double kPi = std::numbers::pi;

void expect_pose_near(const geometry::Pose2D& a, const geometry::Pose2D& b, double tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(geometry::wrap_angle(a.theta - b.theta), 0.0, tolerance);
}

// The path's length by summing short chords: checks that pose_at and length_m agree.
double walked_length_m(const DubinsPath& path) {
  const int steps = 2000;
  double total = 0.0;
  geometry::Pose2D previous = path.pose_at(0.0);
  for (int i = 1; i <= steps; ++i) {
    const geometry::Pose2D next = path.pose_at(path.length_m() * i / steps);
    total += std::hypot(next.x - previous.x, next.y - previous.y);
    previous = next;
  }
  return total;
}

TEST(DubinsPath, AdvanceFollowsTheArc) {
  // A quarter circle of radius 2 to the left from the origin ends at (2, 2) heading north.
  expect_pose_near(advance({0.0, 0.0, 0.0}, 0.5, kPi), {2.0, 2.0, kPi / 2}, 1e-12);
  expect_pose_near(advance({1.0, 1.0, kPi / 2}, 0.0, 3.0), {1.0, 4.0, kPi / 2}, 1e-12);
  expect_pose_near(advance({0.0, 0.0, 0.0}, -0.5, 2.0 * kPi), {0.0, -4.0, kPi}, 1e-12);
  // Nearly straight arcs take the series branch without a jump.
  const geometry::Pose2D a = advance({0.0, 0.0, 0.0}, 1e-7, 1.0);
  EXPECT_NEAR(a.x, 1.0, 1e-12);
  EXPECT_NEAR(a.y, 0.5e-7, 1e-12);
}

TEST(DubinsPath, KnownShortestPaths) {
  const double r = 1.844;
  // Straight ahead.
  EXPECT_NEAR(shortest_dubins_path({0, 0, 0}, {5, 0, 0}, r).length_m(), 5.0, 1e-9);
  // A U-turn onto the parallel lane one turning diameter to the left: half a circle.
  EXPECT_NEAR(shortest_dubins_path({0, 0, 0}, {0, 2 * r, kPi}, r).length_m(), kPi * r, 1e-9);
  // The same pose: nothing to drive.
  EXPECT_NEAR(shortest_dubins_path({1, 2, 0.3}, {1, 2, 0.3}, r).length_m(), 0.0, 1e-9);
  // A quarter turn left of radius r.
  EXPECT_NEAR(shortest_dubins_path({0, 0, 0}, {r, r, kPi / 2}, r).length_m(), kPi * r / 2, 1e-9);
}

TEST(DubinsPath, ShortestPathEndsAtTheGoalWithinTheCurvatureBound) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> position(-8.0, 8.0);
  std::uniform_real_distribution<double> heading(-kPi, kPi);
  for (int trial = 0; trial < 2000; ++trial) {
    const geometry::Pose2D start{position(rng), position(rng), heading(rng)};
    const geometry::Pose2D goal{position(rng), position(rng), heading(rng)};
    const double r = trial % 2 == 0 ? 1.844 : 0.4;
    const DubinsPath path = shortest_dubins_path(start, goal, r);
    expect_pose_near(path.end(), goal, 1e-8);
    EXPECT_LE(path.max_curvature_1pm(), 1.0 / r + 1e-12);
    EXPECT_GE(path.length_m(), std::hypot(goal.x - start.x, goal.y - start.y) - 1e-9);
    EXPECT_NEAR(walked_length_m(path), path.length_m(), 1e-3 * path.length_m() + 1e-9);
    // No shortest path turns more than a full circle in one piece.
    for (const auto& piece : path.pieces())
      EXPECT_LT(std::abs(piece.curvature_1pm) * piece.length_m, 2 * kPi);
  }
}

TEST(DubinsPath, ShortestAmongManySampledDetours) {
  // A brute-force bound: the Dubins length never exceeds a path built from a turn, a straight
  // and a second Dubins path, for random first turns.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> position(-5.0, 5.0);
  std::uniform_real_distribution<double> heading(-kPi, kPi);
  std::uniform_real_distribution<double> turn(-kPi, kPi);
  const double r = 1.0;
  for (int trial = 0; trial < 500; ++trial) {
    const geometry::Pose2D start{0.0, 0.0, heading(rng)};
    const geometry::Pose2D goal{position(rng), position(rng), heading(rng)};
    const double best = shortest_dubins_path(start, goal, r).length_m();
    for (int k = 0; k < 20; ++k) {
      const double angle = turn(rng);
      const geometry::Pose2D via =
          advance(start, angle > 0 ? 1.0 / r : -1.0 / r, std::abs(angle) * r);
      const double detour = std::abs(angle) * r + shortest_dubins_path(via, goal, r).length_m();
      EXPECT_LE(best, detour + 1e-9);
    }
  }
}

TEST(DubinsPath, TurnThenStraightReachesThePoint) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> position(-6.0, 6.0);
  std::uniform_real_distribution<double> heading(-kPi, kPi);
  for (int trial = 0; trial < 1000; ++trial) {
    const geometry::Pose2D start{position(rng), position(rng), heading(rng)};
    const geometry::Point2D point{position(rng), position(rng)};
    const DubinsPath path = turn_then_straight_to_point(start, point, 1.844);
    const geometry::Pose2D end = path.end();
    EXPECT_NEAR(end.x, point.x, 1e-8);
    EXPECT_NEAR(end.y, point.y, 1e-8);
    // It is a Dubins path to its own final heading, and as short as the shortest one there.
    const DubinsPath dubins = shortest_dubins_path(start, end, 1.844);
    EXPECT_LE(path.length_m(), dubins.length_m() + 1e-6);
    EXPECT_LE(path.max_curvature_1pm(), 1.0 / 1.844 + 1e-12);
  }
  // Dead ahead: just the straight.
  EXPECT_NEAR(turn_then_straight_to_point({0, 0, 0}, {4, 0}, 1.0).length_m(), 4.0, 1e-12);
  // Behind: half a turn and back along the other side is longer than the direct distance.
  EXPECT_GT(turn_then_straight_to_point({0, 0, 0}, {-4, 0}, 1.0).length_m(), 4.0 + kPi);
}

TEST(DubinsPath, ArcToAPointAhead) {
  const auto arc = arc_to_point({0, 0, 0}, {1.0, 0.1}, 1.844);
  ASSERT_TRUE(arc.has_value());
  ASSERT_EQ(arc->pieces().size(), 1u);
  EXPECT_NEAR(arc->pieces()[0].curvature_1pm, 2 * 0.1 / 1.01, 1e-12);
  const geometry::Pose2D end = arc->end();
  EXPECT_NEAR(end.x, 1.0, 1e-12);
  EXPECT_NEAR(end.y, 0.1, 1e-12);
  EXPECT_NEAR(end.theta, 2 * std::atan2(0.1, 1.0), 1e-12);
  // Straight ahead: a straight of the distance.
  EXPECT_NEAR(arc_to_point({1, 1, kPi / 2}, {1, 3}, 1.0)->length_m(), 2.0, 1e-12);
  // Too tight, or behind: none.
  EXPECT_FALSE(arc_to_point({0, 0, 0}, {0.5, 0.5}, 1.844).has_value());
  EXPECT_FALSE(arc_to_point({0, 0, 0}, {-1.0, 0.0}, 1.844).has_value());
}

TEST(DubinsPath, RejectsBadPieces) {
  const std::array<DubinsPath::Piece, 4> four{};
  EXPECT_THROW(DubinsPath({}, four), std::invalid_argument);
  const std::array<DubinsPath::Piece, 1> negative{{{0.0, -1.0}}};
  EXPECT_THROW(DubinsPath({}, negative), std::invalid_argument);
}

}  // namespace
}  // namespace mobot::planning
