#include "core/safety/sonar_emergency_rules.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace mobot::safety {
namespace {

// The Dashgo's ring (R2): s0 front left, s1 front, s2 front right, s3 rear; 0.8 m means no echo.
msgs::SonarRing ring(double s0, double s1, double s2, double s3) {
  msgs::SonarRing out;
  const geometry::Pose2D mounts[] = {{0.18, 0.10, std::numbers::pi / 6},
                                     {0.20, 0.0, 0.0},
                                     {0.18, -0.10, -std::numbers::pi / 6},
                                     {-0.20, 0.0, std::numbers::pi}};
  const double ranges[] = {s0, s1, s2, s3};
  for (int i = 0; i < 4; ++i) out.readings.push_back({mounts[i], 0.3, 0.03, 0.8, ranges[i]});
  return out;
}

constexpr double kFar = 0.8;
const BaseMotion kForward{{0.3, 0.0}, {0.3, 0.0}};
const BaseMotion kReversing{{-0.2, 0.0}, {-0.2, 0.0}};
const BaseMotion kStill{};

TEST(SonarEmergency, FrontSonarWithinSevenCentimetresStopsAForwardBase) {
  const auto fired = sonar_emergency(ring(kFar, 0.07, kFar, kFar), kForward);
  ASSERT_TRUE(fired);
  EXPECT_EQ(fired->rule, SonarRule::kFrontStop);
  EXPECT_EQ(fired->sensor, 1U);
  EXPECT_DOUBLE_EQ(fired->range_m, 0.07);
  EXPECT_EQ(fired->command, (msgs::Twist{}));
  EXPECT_EQ(to_string(fired->rule), "front_stop");
  EXPECT_EQ(reaction_of(fired->rule), "stop");
  EXPECT_FALSE(sonar_emergency(ring(kFar, 0.071, kFar, kFar), kForward)) << "just outside";
}

TEST(SonarEmergency, RearSonarStopsOnlyAReversingBase) {
  const auto fired = sonar_emergency(ring(kFar, kFar, kFar, 0.05), kReversing);
  ASSERT_TRUE(fired);
  EXPECT_EQ(fired->rule, SonarRule::kRearStop);
  EXPECT_EQ(fired->sensor, 3U);
  EXPECT_EQ(reaction_of(fired->rule), "stop");
  // Something behind while driving forward is no danger.
  EXPECT_FALSE(sonar_emergency(ring(kFar, kFar, kFar, 0.05), kForward));
  // Something in front while reversing away from it is none either.
  EXPECT_FALSE(sonar_emergency(ring(0.05, 0.05, 0.05, kFar), kReversing));
}

TEST(SonarEmergency, SideSonarsTurnAwayAtTheRuleRate) {
  const auto left = sonar_emergency(ring(0.10, kFar, kFar, kFar), kForward);
  ASSERT_TRUE(left);
  EXPECT_EQ(left->rule, SonarRule::kTurnRight);
  EXPECT_EQ(left->sensor, 0U);
  EXPECT_EQ(left->command, (msgs::Twist{0.0, -0.2}));
  EXPECT_EQ(reaction_of(left->rule), "turn_right");

  const auto right = sonar_emergency(ring(kFar, kFar, 0.08, kFar), kForward);
  ASSERT_TRUE(right);
  EXPECT_EQ(right->rule, SonarRule::kTurnLeft);
  EXPECT_EQ(right->sensor, 2U);
  EXPECT_EQ(right->command, (msgs::Twist{0.0, 0.2}));

  EXPECT_FALSE(sonar_emergency(ring(0.101, kFar, 0.12, kFar), kForward));
  EXPECT_FALSE(sonar_emergency(ring(0.05, kFar, 0.05, kFar), kReversing)) << "only forward";
}

TEST(SonarEmergency, BothSidesTurnAwayFromTheNearerAndStopsWin) {
  const auto nearer_left = sonar_emergency(ring(0.04, kFar, 0.09, kFar), kForward);
  ASSERT_TRUE(nearer_left);
  EXPECT_EQ(nearer_left->rule, SonarRule::kTurnRight);
  const auto tie = sonar_emergency(ring(0.06, kFar, 0.06, kFar), kForward);
  ASSERT_TRUE(tie);
  EXPECT_EQ(tie->rule, SonarRule::kTurnLeft);
  // The front stop overrides a turn.
  const auto all = sonar_emergency(ring(0.04, 0.05, 0.09, kFar), kForward);
  ASSERT_TRUE(all);
  EXPECT_EQ(all->rule, SonarRule::kFrontStop);
}

TEST(SonarEmergency, AStationaryBaseFiresNothing) {
  EXPECT_FALSE(sonar_emergency(ring(0.03, 0.03, 0.03, 0.03), kStill));
  // Creeping below the threshold is standing still; a command to move is moving.
  EXPECT_FALSE(sonar_emergency(ring(kFar, 0.03, kFar, kFar), {{0.004, 0.0}, {0.0, 0.0}}));
  EXPECT_TRUE(sonar_emergency(ring(kFar, 0.03, kFar, kFar), {{0.05, 0.0}, {0.0, 0.0}}));
  // Still skidding forward after the command dropped: the measurement says it moves.
  EXPECT_TRUE(sonar_emergency(ring(kFar, 0.03, kFar, kFar), {{0.0, 0.0}, {0.1, 0.0}}));
  // Turning on the spot closes on nothing.
  EXPECT_FALSE(sonar_emergency(ring(0.03, 0.03, 0.03, 0.03), {{0.0, 0.7}, {0.0, 0.7}}));
}

TEST(SonarEmergency, BrokenReadingsAndMissingSonarsAreIgnored) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(sonar_emergency(ring(nan, nan, nan, nan), kForward));
  EXPECT_FALSE(sonar_emergency(ring(-0.01, -1.0, -inf, kFar), kForward));
  EXPECT_FALSE(sonar_emergency(ring(inf, inf, inf, inf), kReversing));
  EXPECT_FALSE(sonar_emergency(msgs::SonarRing{}, kForward)) << "an empty ring";
  // A ring with the front sonars only: the rear rule has nothing to read.
  msgs::SonarRing front_only = ring(kFar, kFar, kFar, 0.01);
  front_only.readings.pop_back();
  EXPECT_FALSE(sonar_emergency(front_only, kReversing));
  // A non-finite speed counts as not moving.
  EXPECT_FALSE(sonar_emergency(ring(kFar, 0.03, kFar, kFar), {{nan, 0.0}, {inf, 0.0}}));
}

TEST(SonarEmergency, RejectsNegativeOrNonFiniteOptions) {
  SonarEmergencyOptions options;
  options.front_stop_distance_m = -0.1;
  EXPECT_THROW(sonar_emergency(ring(kFar, kFar, kFar, kFar), kForward, options),
               std::invalid_argument);
  options = {};
  options.turn_rate_radps = std::nan("");
  EXPECT_THROW(sonar_emergency(ring(kFar, kFar, kFar, kFar), kForward, options),
               std::invalid_argument);
  // Other indices: a ring wired differently.
  options = {};
  options.front_index = 3;
  options.rear_index = 1;
  const auto fired = sonar_emergency(ring(kFar, kFar, kFar, 0.05), kForward, options);
  ASSERT_TRUE(fired);
  EXPECT_EQ(fired->rule, SonarRule::kFrontStop);
  EXPECT_EQ(fired->sensor, 3U);
}

}  // namespace
}  // namespace mobot::safety
