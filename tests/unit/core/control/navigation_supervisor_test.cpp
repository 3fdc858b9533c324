#include "core/control/navigation_supervisor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/control/waypoint_follower.h"
#include "core/planning/path_smoother.h"

namespace mobot::control {
namespace {

constexpr double kPi = std::numbers::pi;

double deg(double degrees) { return degrees * kPi / 180.0; }

msgs::RangeReading ahead(double range_m) {
  msgs::RangeReading r;
  r.sensor_in_base = {0.3, 0.0, 0.0};
  r.cone_rad = deg(22.5);
  r.range_min_m = 0.03;
  r.range_max_m = 4.0;
  r.range_m = range_m;
  return r;
}

planning::Path straight(double length_m) {
  return planning::Path(planning::PathSmoother::densify({{0.0, 0.0}, {length_m, 0.0}}, 0.3));
}

NavigationSupervisor make_supervisor() { return NavigationSupervisor({}, PotentialFieldOptions{}); }

TEST(NavigationSupervisor, IdlesWithoutAPath) {
  NavigationSupervisor supervisor = make_supervisor();
  const std::vector<msgs::RangeReading> near{ahead(0.2)};
  EXPECT_EQ(supervisor.update(0.0, {}, near).mode, NavigationMode::kIdle);
  supervisor.set_path(planning::Path(), 0.0);
  EXPECT_EQ(supervisor.update(0.1, {}, near).mode, NavigationMode::kIdle);
}

TEST(NavigationSupervisor, AvoidsWhileAnObstacleIsNearAndResumesAfterTheHold) {
  NavigationSupervisor supervisor = make_supervisor();
  supervisor.set_path(straight(10.0), 0.0);
  const std::vector<msgs::RangeReading> clear{ahead(3.0)};
  const std::vector<msgs::RangeReading> near{ahead(0.5)};
  EXPECT_EQ(supervisor.update(0.0, {0.0, 0.0, 0.0}, clear).mode, NavigationMode::kTracking);
  const auto entered = supervisor.update(0.1, {0.1, 0.0, 0.0}, near);
  EXPECT_EQ(entered.mode, NavigationMode::kAvoiding);
  EXPECT_TRUE(entered.entered_avoidance);
  EXPECT_NEAR(entered.rejoin_point.x, 0.1 + 1.5, 1e-9);  // on the path, 1.5 m ahead
  EXPECT_FALSE(supervisor.update(0.2, {0.2, 0.1, 0.0}, near).entered_avoidance);
  // Clear, but not for long enough yet.
  EXPECT_EQ(supervisor.update(0.3, {0.3, 0.2, 0.0}, clear).mode, NavigationMode::kAvoiding);
  EXPECT_EQ(supervisor.update(0.7, {0.4, 0.2, 0.0}, clear).mode, NavigationMode::kAvoiding);
  // An echo in between restarts the hold.
  EXPECT_EQ(supervisor.update(0.75, {0.45, 0.2, 0.0}, near).mode, NavigationMode::kAvoiding);
  EXPECT_EQ(supervisor.update(1.0, {0.5, 0.2, 0.0}, clear).mode, NavigationMode::kAvoiding);
  EXPECT_EQ(supervisor.update(1.5, {0.6, 0.2, 0.0}, clear).mode, NavigationMode::kTracking);
}

TEST(NavigationSupervisor, ReportsBlockedWhenAvoidanceMakesNoProgress) {
  NavigationSupervisor supervisor = make_supervisor();  // 5 s, 0.2 m
  supervisor.set_path(straight(10.0), 0.0);
  const std::vector<msgs::RangeReading> near{ahead(0.4)};
  EXPECT_EQ(supervisor.update(1.0, {1.0, 0.0, 0.0}, near).mode, NavigationMode::kAvoiding);
  // Wiggling on the spot for 4.9 s: still avoiding.
  for (double t = 1.1; t < 5.95; t += 0.1) {
    ASSERT_EQ(supervisor.update(t, {1.0 + 0.05 * std::sin(t), 0.3, 0.0}, near).mode,
              NavigationMode::kAvoiding)
        << t;
  }
  EXPECT_EQ(supervisor.update(6.0, {1.1, 0.3, 0.0}, near).mode, NavigationMode::kBlocked);
  // Latched until a new path arrives, even when the obstacle goes away.
  const std::vector<msgs::RangeReading> clear{ahead(3.0)};
  EXPECT_EQ(supervisor.update(7.0, {1.1, 0.3, 0.0}, clear).mode, NavigationMode::kBlocked);
  supervisor.set_path(straight(10.0), 7.0);
  EXPECT_EQ(supervisor.update(7.1, {1.1, 0.3, 0.0}, clear).mode, NavigationMode::kTracking);
}

TEST(NavigationSupervisor, ProgressAlongThePathKeepsAvoidanceGoing) {
  NavigationSupervisor supervisor = make_supervisor();
  supervisor.set_path(straight(20.0), 0.0);
  const std::vector<msgs::RangeReading> near{ahead(0.6)};
  // A long wall alongside: avoiding for 12 s but moving 0.1 m/s along the path.
  for (double t = 0.0; t < 12.0; t += 0.1) {
    ASSERT_EQ(supervisor.update(t, {0.1 * t, 0.5, 0.0}, near).mode,
              t == 0.0 ? NavigationMode::kAvoiding : NavigationMode::kAvoiding);
  }
  EXPECT_NEAR(supervisor.update(12.0, {1.2, 0.5, 0.0}, near).progress_m, 1.2, 1e-9);
}

TEST(NavigationSupervisor, IgnoresNonFinitePoses) {
  NavigationSupervisor supervisor = make_supervisor();
  supervisor.set_path(straight(5.0), 0.0);
  const std::vector<msgs::RangeReading> near{ahead(0.2)};
  EXPECT_EQ(supervisor.update(0.1, {std::nan(""), 0.0, 0.0}, near).mode, NavigationMode::kTracking);
  EXPECT_THROW(NavigationSupervisor({-1.0}, PotentialFieldOptions{}), std::invalid_argument);
}

// R1's sonar ring (chosen layout): 6 facing forward around the front edge, one per side.
std::vector<msgs::RangeReading> r1_ring() {
  std::vector<msgs::RangeReading> ring;
  for (const double bearing : {-90.0, -50.0, -30.0, -10.0, 10.0, 30.0, 50.0, 90.0}) {
    msgs::RangeReading r;
    const double b = deg(bearing);
    const bool side = std::abs(bearing) == 90.0;
    r.sensor_in_base = side ? geometry::Pose2D{0.0, 0.3 * std::sin(b), b}
                            : geometry::Pose2D{0.3, 0.3 * std::sin(b), b};
    r.cone_rad = deg(22.5);
    r.range_min_m = 0.03;
    r.range_max_m = 4.0;
    ring.push_back(r);
  }
  return ring;
}

// Nearest hit of a few rays across each cone with a disc obstacle.
void sense(std::vector<msgs::RangeReading>& ring, const geometry::Pose2D& robot,
           geometry::Point2D centre, double radius) {
  for (auto& r : ring) {
    r.range_m = r.range_max_m;
    const geometry::Pose2D sensor = geometry::compose(robot, r.sensor_in_base);
    for (int k = -2; k <= 2; ++k) {
      const double a = sensor.theta + k * r.cone_rad / 4.0;
      const double dx = std::cos(a);
      const double dy = std::sin(a);
      const double fx = sensor.x - centre.x;
      const double fy = sensor.y - centre.y;
      const double b = fx * dx + fy * dy;
      const double c = fx * fx + fy * fy - radius * radius;
      const double disc = b * b - c;
      if (disc < 0.0) continue;
      const double t = -b - std::sqrt(disc);
      if (t > 0.0) r.range_m = std::min(r.range_m, std::max(t, r.range_min_m));
    }
  }
}

TEST(NavigationSupervisor, ClosedLoopAvoidsAnObstacleDroppedOnThePathAndRejoinsIt) {
  // C4's scene: a 6 m straight path; an obstacle of radius 0.2 m appears on it at x = 3.
  const planning::Path path = straight(6.0);
  WaypointFollower follower;
  ASSERT_TRUE(follower.set_path(path, 0.0));
  NavigationSupervisor supervisor = make_supervisor();
  supervisor.set_path(path, 0.0);
  PotentialFieldAvoider avoider;
  std::vector<msgs::RangeReading> ring = r1_ring();
  const geometry::Point2D obstacle{3.0, 0.05};
  const double obstacle_radius = 0.2;

  geometry::Pose2D pose{};
  msgs::Twist velocity;
  double min_clearance = 1e9;
  bool avoided = false;
  double max_offset_after = 0.0;
  constexpr double kDt = 0.02;
  for (double t = 0.0; t < 60.0 && !follower.arrived(); t += kDt) {
    sense(ring, pose, obstacle, obstacle_radius);
    const auto decision = supervisor.update(t, pose, ring);
    ASSERT_NE(decision.mode, NavigationMode::kBlocked) << t;
    if (decision.entered_avoidance) avoider.reset();
    msgs::Twist u;
    if (decision.mode == NavigationMode::kAvoiding) {
      avoided = true;
      u = avoider.compute(pose, decision.rejoin_point, ring).command;
    } else {
      u = follower.compute(pose, velocity, t);
    }
    pose.x += u.linear_mps * std::cos(pose.theta) * kDt;
    pose.y += u.linear_mps * std::sin(pose.theta) * kDt;
    pose.theta = geometry::wrap_angle(pose.theta + u.angular_radps * kDt);
    velocity = u;
    min_clearance = std::min(
        min_clearance, std::hypot(pose.x - obstacle.x, pose.y - obstacle.y) - obstacle_radius);
    if (pose.x > 4.5) max_offset_after = std::max(max_offset_after, std::abs(pose.y));
  }
  EXPECT_TRUE(avoided);
  EXPECT_TRUE(follower.arrived());
  EXPECT_GT(min_clearance, 0.3);     // the inscribed radius: no contact
  EXPECT_LT(max_offset_after, 0.3);  // back on the path after the obstacle
  EXPECT_LT(std::hypot(pose.x - 6.0, pose.y), 0.05);
}

}  // namespace
}  // namespace mobot::control
