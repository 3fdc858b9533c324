#include "core/control/potential_field_avoider.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace mobot::control {
namespace {

constexpr double kPi = std::numbers::pi;

double deg(double degrees) { return degrees * kPi / 180.0; }

// A sonar at the robot centre looking along `bearing` (so the echo bearing equals it).
msgs::RangeReading reading(double bearing_rad, double range_m) {
  msgs::RangeReading r;
  r.sensor_in_base = {0.0, 0.0, bearing_rad};
  r.cone_rad = deg(22.5);
  r.range_min_m = 0.03;
  r.range_max_m = 4.0;
  r.range_m = range_m;
  return r;
}

TEST(PotentialFieldAvoider, ActivatesOnlyForNearEchoesInTheFrontSector) {
  const PotentialFieldAvoider avoider;
  const auto active = [&](double bearing_deg, double range) {
    const std::vector<msgs::RangeReading> readings{reading(deg(bearing_deg), range)};
    return avoider.is_active(readings);
  };
  EXPECT_TRUE(active(0.0, 0.69));
  EXPECT_FALSE(active(0.0, 0.71));
  EXPECT_TRUE(active(59.0, 0.5));
  EXPECT_TRUE(active(-59.0, 0.5));
  EXPECT_FALSE(active(61.0, 0.5));
  EXPECT_FALSE(active(-90.0, 0.1));
  EXPECT_FALSE(active(180.0, 0.1));
  EXPECT_FALSE(active(0.0, 4.0));           // range_max: no echo
  EXPECT_FALSE(active(0.0, std::nan("")));  // broken reading
  EXPECT_FALSE(active(0.0, 0.01));          // below range_min
  EXPECT_FALSE(avoider.is_active({}));
}

TEST(PotentialFieldAvoider, UsesTheEchoBearingSeenFromTheRobotCentre) {
  // A side sonar at (0, 0.3) looking 45 degrees out: its echo at 0.5 m lies at bearing
  // atan2(0.3 + 0.354, 0.354) = 61.5 degrees: outside the sector although the sensor looks at 45.
  msgs::RangeReading side = reading(deg(45.0), 0.5);
  side.sensor_in_base = {0.0, 0.3, deg(45.0)};
  const auto obstacle = PotentialFieldAvoider::to_obstacle(side);
  ASSERT_TRUE(obstacle.has_value());
  EXPECT_NEAR(obstacle->bearing_rad, std::atan2(0.3 + 0.5 * std::sqrt(0.5), 0.5 * std::sqrt(0.5)),
              1e-12);
  const std::vector<msgs::RangeReading> readings{side};
  EXPECT_FALSE(PotentialFieldAvoider().is_active(readings));
}

TEST(PotentialFieldAvoider, SteersAwayFromTheObstacleSide) {
  const geometry::Pose2D pose{0.0, 0.0, 0.0};
  const geometry::Point2D goal{3.0, 0.0};
  {
    PotentialFieldAvoider avoider;
    const std::vector<msgs::RangeReading> left{reading(deg(15.0), 0.5)};
    const auto out = avoider.compute(pose, goal, left);
    EXPECT_EQ(out.obstacle_side, 1);
    EXPECT_NEAR(out.steer_heading_rad, deg(-60.0), 1e-12);
    EXPECT_LT(out.command.angular_radps, 0.0);  // turn right, away from the left obstacle
  }
  {
    PotentialFieldAvoider avoider;
    const std::vector<msgs::RangeReading> right{reading(deg(-15.0), 0.5)};
    const auto out = avoider.compute(pose, goal, right);
    EXPECT_EQ(out.obstacle_side, -1);
    EXPECT_NEAR(out.steer_heading_rad, deg(60.0), 1e-12);
    EXPECT_GT(out.command.angular_radps, 0.0);
  }
  {
    // The steering is relative to the goal bearing, not the heading.
    PotentialFieldAvoider avoider;
    const std::vector<msgs::RangeReading> left{reading(deg(15.0), 0.5)};
    const auto out = avoider.compute(pose, {3.0, 3.0}, left);
    EXPECT_NEAR(out.steer_heading_rad, deg(45.0 - 60.0), 1e-12);
  }
}

TEST(PotentialFieldAvoider, RepulsionFollowsC4AndPushesBackAlongTheHeading) {
  PotentialFieldAvoider avoider;
  const geometry::Pose2D pose{1.0, 2.0, deg(30.0)};
  const geometry::Point2D goal{1.0 + 2.0 * std::cos(deg(30.0)), 2.0 + 2.0 * std::sin(deg(30.0))};
  const std::vector<msgs::RangeReading> none;
  const auto free = avoider.compute(pose, goal, none);
  EXPECT_NEAR(free.v_attractive_mps, 10.0 * 2.0, 1e-9);  // k_att times the distance along heading
  EXPECT_DOUBLE_EQ(free.v_repulsive_mps, 0.0);
  EXPECT_EQ(free.obstacle_side, 0);

  const double d = 0.4;
  const std::vector<msgs::RangeReading> ahead{reading(0.0, d), reading(deg(40.0), 0.9)};
  const auto out = avoider.compute(pose, goal, ahead);
  EXPECT_NEAR(out.v_repulsive_mps, 10.0 * (1.0 / d - 1.0 / 0.7) / (d * d), 1e-9);
  // 20 - 67 < 0: the robot stops (forward-only by default) ...
  EXPECT_DOUBLE_EQ(out.command.linear_mps, 0.0);
  // ... or backs off when allowed, clamped to the limit.
  PotentialFieldOptions options;
  options.allow_reverse = true;
  PotentialFieldAvoider reverse(options);
  EXPECT_DOUBLE_EQ(reverse.compute(pose, goal, ahead).command.linear_mps, -0.45);
  // An echo at an angle pushes back by its component along the heading only.
  PotentialFieldAvoider angled;
  const std::vector<msgs::RangeReading> oblique{reading(deg(50.0), d)};
  EXPECT_NEAR(angled.compute(pose, goal, oblique).v_repulsive_mps,
              10.0 * (1.0 / d - 1.0 / 0.7) / (d * d) * std::cos(deg(50.0)), 1e-9);
}

TEST(PotentialFieldAvoider, ClampsEverythingToTheLimits) {
  PotentialFieldOptions options;
  options.max_linear_mps = 0.3;
  options.max_angular_radps = 0.5;
  PotentialFieldAvoider avoider(options);
  const auto out = avoider.compute({0.0, 0.0, 0.0}, {-5.0, 5.0}, {});
  EXPECT_DOUBLE_EQ(out.command.linear_mps, 0.0);  // goal behind: v_att < 0, forward only
  EXPECT_DOUBLE_EQ(out.command.angular_radps, 0.5);
  const auto fast = avoider.compute({0.0, 0.0, 0.0}, {50.0, 0.0}, {});
  EXPECT_DOUBLE_EQ(fast.command.linear_mps, 0.3);
  EXPECT_DOUBLE_EQ(fast.command.angular_radps, 0.0);
}

TEST(PotentialFieldAvoider, KeepsItsSideWhenTheObstacleIsDeadAhead) {
  PotentialFieldAvoider avoider;
  const geometry::Pose2D pose{};
  const std::vector<msgs::RangeReading> left{reading(deg(20.0), 0.5)};
  EXPECT_EQ(avoider.compute(pose, {3.0, 0.0}, left).obstacle_side, 1);
  // Nearly balanced, slightly more on the right: keep turning the way we chose.
  const std::vector<msgs::RangeReading> balanced{reading(deg(5.0), 0.50), reading(deg(-5.0), 0.49)};
  EXPECT_EQ(avoider.compute(pose, {3.0, 0.0}, balanced).obstacle_side, 1);
  // Clearly on the right now: switch.
  const std::vector<msgs::RangeReading> right{reading(deg(-20.0), 0.4)};
  EXPECT_EQ(avoider.compute(pose, {3.0, 0.0}, right).obstacle_side, -1);
  avoider.reset();
  EXPECT_EQ(avoider.compute(pose, {3.0, 0.0}, balanced).obstacle_side, -1);
}

TEST(PotentialFieldAvoider, NonFiniteInputStopsAndBadOptionsThrow) {
  PotentialFieldAvoider avoider;
  EXPECT_EQ(avoider.compute({std::nan(""), 0.0, 0.0}, {1.0, 0.0}, {}).command, msgs::Twist{});
  EXPECT_EQ(avoider.compute({}, {1.0, INFINITY}, {}).command, msgs::Twist{});
  PotentialFieldOptions bad;
  bad.influence_distance_m = 0.0;
  EXPECT_THROW(PotentialFieldAvoider{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace mobot::control
