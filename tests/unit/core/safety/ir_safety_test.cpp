#include "core/safety/ir_safety.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <numbers>

namespace mobot::safety {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRing_s = 0.05;  // 20 Hz
constexpr double kNothing = 0.8;  // the Sharp's range_max: no object in range

// The Dashgo's ring (R2): index -> bearing in degrees.
constexpr double kBearingsDeg[] = {-45, -25, -10, 0, 10, 25, 45, 155, 180, 205};
constexpr std::size_t kAhead = 3;
constexpr std::size_t kLeft10 = 4;
constexpr std::size_t kLeft25 = 5;
constexpr std::size_t kRight10 = 2;
constexpr std::size_t kRearLeft = 7;  // 155 deg
constexpr std::size_t kBehind = 8;

msgs::IrRing ring(const std::map<std::size_t, double>& ranges = {}) {
  msgs::IrRing out;
  for (std::size_t i = 0; i < std::size(kBearingsDeg); ++i) {
    const double bearing = geometry::wrap_angle(kBearingsDeg[i] * kPi / 180.0);
    const auto found = ranges.find(i);
    out.readings.push_back({{0.145 * std::cos(bearing), 0.145 * std::sin(bearing), bearing},
                            0.1,
                            0.10,
                            0.80,
                            found == ranges.end() ? kNothing : found->second});
  }
  return out;
}

BaseMotion moving(double linear_mps) { return {{linear_mps, 0.0}, {linear_mps, 0.0}}; }

// Steps at the ring's rate with a new ring each time.
class IrSafetyRun {
 public:
  explicit IrSafetyRun(IrSafetyOptions options = {}) : safety_(std::move(options)) {}

  std::optional<IrSafetyDecision> step(const msgs::IrRing& ir, const BaseMotion& motion) {
    t_s_ += kRing_s;
    return safety_.step(ir, motion, t_s_);
  }
  std::optional<IrSafetyDecision> step_without_ring(const BaseMotion& motion, double dt_s) {
    t_s_ += dt_s;
    return safety_.step(std::nullopt, motion, t_s_);
  }
  IrSafety& safety() { return safety_; }

 private:
  IrSafety safety_;
  double t_s_ = 0.0;
};

TEST(IrSafety, UrgentZoneStopsBacksOffAndEnds) {
  IrSafetyRun run;
  // 0.12 m ahead of the sensor at 0.145 m: 0.265 m from the centre, inside U (0.30 m).
  const msgs::IrRing close = ring({{kAhead, 0.12}});
  EXPECT_FALSE(run.step(close, moving(0.3))) << "one ring is not enough: Sharp sensors spike";
  auto decision = run.step(close, moving(0.3));
  ASSERT_TRUE(decision);
  EXPECT_EQ(decision->zone, IrZone::kUrgent);
  EXPECT_EQ(decision->reaction, IrReaction::kStop);
  EXPECT_EQ(decision->sensor, kAhead);
  EXPECT_DOUBLE_EQ(decision->range_m, 0.12);
  EXPECT_TRUE(decision->alarm);
  EXPECT_EQ(decision->command, (msgs::Twist{}));
  EXPECT_EQ(to_string(decision->zone), "urgent");
  EXPECT_EQ(to_string(decision->reaction), "stop");

  // Still rolling: the stop holds.
  decision = run.step(close, {{0.0, 0.0}, {0.2, 0.0}});
  ASSERT_TRUE(decision);
  EXPECT_EQ(decision->reaction, IrReaction::kStop);
  // Stopped: back off, away from the obstacle in front.
  decision = run.step(close, {{0.0, 0.0}, {0.0, 0.0}});
  ASSERT_TRUE(decision);
  EXPECT_EQ(decision->reaction, IrReaction::kBackOff);
  EXPECT_EQ(to_string(decision->reaction), "back_off");
  EXPECT_EQ(decision->command, (msgs::Twist{-0.10, 0.0}));
  EXPECT_EQ(decision->zone, IrZone::kUrgent);

  // Reversing at 0.1 m/s the back-off ends after its 0.10 m.
  int ticks = 0;
  while (run.step(close, moving(-0.1))) ASSERT_LT(++ticks, 100);
  EXPECT_NEAR(ticks, 20, 1) << "0.10 m at 0.10 m/s, one ring every 0.05 s";
}

TEST(IrSafety, TheStopTurnsIntoABackOffAfterAWhileEvenIfTheOdometryStillShowsMotion) {
  IrSafetyRun run;
  const msgs::IrRing close = ring({{kAhead, 0.12}});
  run.step(close, moving(0.3));
  ASSERT_TRUE(run.step(close, moving(0.3)));
  int ticks = 0;
  while (run.step(close, {{0.0, 0.0}, {0.2, 0.0}})->reaction == IrReaction::kStop) {
    ASSERT_LT(++ticks, 100);
  }
  EXPECT_NEAR(ticks * kRing_s, 0.5, kRing_s + 1e-9) << "stop_max_s";
}

TEST(IrSafety, TheBackOffEndsOnceTheObstacleHasLeftTheZone) {
  IrSafetyRun run;
  run.step(ring({{kAhead, 0.12}}), moving(0.3));
  run.step(ring({{kAhead, 0.12}}), moving(0.3));
  ASSERT_EQ(run.step(ring({{kAhead, 0.12}}), {})->reaction, IrReaction::kBackOff);
  // 0.145 + 0.20 = 0.345 m from the centre: still within U's 5 cm margin; 0.355 m is out.
  EXPECT_TRUE(run.step(ring({{kAhead, 0.20}}), moving(-0.1)));
  EXPECT_FALSE(run.step(ring({{kAhead, 0.21}}), moving(-0.1)));
}

TEST(IrSafety, UrgentNeedsMotionTowardTheObstacle) {
  const msgs::IrRing ahead = ring({{kAhead, 0.12}});
  const msgs::IrRing behind = ring({{kBehind, 0.12}});
  {
    IrSafetyRun still;
    for (int i = 0; i < 5; ++i) EXPECT_FALSE(still.step(ahead, {})) << "a stationary base";
  }
  {
    IrSafetyRun away;
    for (int i = 0; i < 5; ++i) EXPECT_FALSE(away.step(behind, moving(0.3))) << "behind";
    for (int i = 0; i < 5; ++i) EXPECT_FALSE(away.step(ahead, moving(-0.3))) << "reversing";
  }
  {
    IrSafetyRun spinning;
    const BaseMotion turning{{0.0, 0.7}, {0.0, 0.7}};
    for (int i = 0; i < 5; ++i) EXPECT_FALSE(spinning.step(ahead, turning)) << "on the spot";
  }
  {
    // Told to go forward while still standing: the command counts.
    IrSafetyRun starting;
    starting.step(ahead, {{0.2, 0.0}, {0.0, 0.0}});
    EXPECT_TRUE(starting.step(ahead, {{0.2, 0.0}, {0.0, 0.0}}));
  }
  {
    // Reversing into something behind: stop, then back off forward.
    IrSafetyRun reversing;
    reversing.step(behind, moving(-0.2));
    const auto decision = reversing.step(behind, moving(-0.2));
    ASSERT_TRUE(decision);
    EXPECT_EQ(decision->sensor, kBehind);
    const auto back_off = reversing.step(behind, {});
    ASSERT_TRUE(back_off);
    EXPECT_EQ(back_off->command, (msgs::Twist{0.10, 0.0}));
  }
}

TEST(IrSafety, ASingleSpikeStartsNothing) {
  IrSafetyRun run;
  for (int i = 0; i < 10; ++i) {
    EXPECT_FALSE(run.step(i % 2 == 0 ? ring({{kAhead, 0.10}}) : ring(), moving(0.5))) << i;
  }
  // One ring is enough when told so.
  IrSafetyOptions options;
  options.confirm_rings = 1;
  IrSafetyRun eager(options);
  EXPECT_TRUE(eager.step(ring({{kAhead, 0.10}}), moving(0.5)));
}

TEST(IrSafety, TheBackOffDoesNotRunIntoWhatIsBehind) {
  IrSafetyRun run;
  // Behind: 0.145 + 0.2 = 0.345 m, within U plus the 0.10 m the back-off would travel.
  const msgs::IrRing boxed = ring({{kAhead, 0.12}, {kBehind, 0.2}});
  run.step(boxed, moving(0.3));
  ASSERT_TRUE(run.step(boxed, moving(0.3)));
  EXPECT_FALSE(run.step(boxed, {})) << "stopped, and it cannot back off: the reaction ends";
  // Something appearing behind during the back-off ends it too.
  IrSafetyRun later;
  later.step(ring({{kAhead, 0.12}}), moving(0.3));
  later.step(ring({{kAhead, 0.12}}), moving(0.3));
  ASSERT_EQ(later.step(ring({{kAhead, 0.12}}), {})->reaction, IrReaction::kBackOff);
  EXPECT_FALSE(later.step(ring({{kAhead, 0.12}, {kBehind, 0.10}}), moving(-0.1)));
}

TEST(IrSafety, TheBubbleGrowsWithSpeedAlongEachSensor) {
  const IrSafety safety;
  const msgs::IrRing r = ring();
  // bb = K V dt = 24 * 0.5 * 0.05 = 0.6 m dead ahead; cos(45 deg) of it on the diagonals.
  EXPECT_NEAR(safety.bubble_m(r.readings[kAhead], kAhead, 0.5, 0.0), 0.6, 1e-12);
  EXPECT_NEAR(safety.bubble_m(r.readings[0], 0, 0.5, 0.0), 0.6 * std::cos(kPi / 4), 1e-12);
  EXPECT_DOUBLE_EQ(safety.bubble_m(r.readings[kAhead], kAhead, 1.0, 0.0), 0.7) << "capped";
  EXPECT_DOUBLE_EQ(safety.bubble_m(r.readings[kBehind], kBehind, 0.5, 0.0), 0.0) << "behind";
  EXPECT_NEAR(safety.bubble_m(r.readings[kBehind], kBehind, 0.0, 0.5), 0.6, 1e-12);
  EXPECT_DOUBLE_EQ(safety.bubble_m(r.readings[kAhead], kAhead, 0.0, 0.0), 0.0);
  // Per-sensor gains; the ones not given use the common gain.
  IrSafetyOptions options;
  options.bubble_gains = {0.0, 0.0, 0.0, 12.0};
  const IrSafety tuned(options);
  EXPECT_NEAR(tuned.bubble_m(r.readings[kAhead], kAhead, 0.5, 0.0), 0.3, 1e-12);
  EXPECT_DOUBLE_EQ(tuned.bubble_m(r.readings[0], 0, 0.5, 0.0), 0.0);
  EXPECT_NEAR(tuned.bubble_m(r.readings[kLeft10], kLeft10, 0.5, 0.0),
              0.6 * std::cos(10 * kPi / 180), 1e-12);
}

TEST(IrSafety, TheBubbleTurnsAwayFromTheSideWithMoreHitsThenEnds) {
  IrSafetyRun run;
  // Two hits on the left (+10, +25 deg) at 0.5 m, one on the right (-10 deg): inside bubbles of
  // 0.59 m and 0.54 m at 0.5 m/s, far outside U.
  const msgs::IrRing left_heavy = ring({{kLeft10, 0.5}, {kLeft25, 0.5}, {kRight10, 0.45}});
  EXPECT_FALSE(run.step(left_heavy, moving(0.5)));
  auto decision = run.step(left_heavy, moving(0.5));
  ASSERT_TRUE(decision);
  EXPECT_EQ(decision->zone, IrZone::kBubble);
  EXPECT_EQ(decision->reaction, IrReaction::kTurnRight);
  EXPECT_EQ(decision->sensor, kRight10) << "the nearest hit";
  EXPECT_FALSE(decision->alarm);
  EXPECT_EQ(decision->command, (msgs::Twist{0.0, -0.4}));
  EXPECT_EQ(to_string(decision->zone), "bubble");
  // Turning on the spot the base no longer moves, but the bubble it had still counts.
  decision = run.step(left_heavy, {{0.0, -0.4}, {0.0, -0.4}});
  ASSERT_TRUE(decision);
  EXPECT_EQ(decision->reaction, IrReaction::kTurnRight);
  EXPECT_FALSE(run.step(ring(), {{0.0, -0.4}, {0.0, -0.4}})) << "clear: the reaction ends";
}

TEST(IrSafety, ABubbleHitDeadAheadTurnsTowardTheRoomierSide) {
  IrSafetyRun run;
  // One hit straight ahead; the right side sees a wall at 0.65 m (outside every bubble), the
  // left nothing.
  const msgs::IrRing ahead = ring({{kAhead, 0.4}, {0, 0.65}, {1, 0.65}, {kRight10, 0.65}});
  run.step(ahead, moving(0.5));
  const auto decision = run.step(ahead, moving(0.5));
  ASSERT_TRUE(decision);
  EXPECT_EQ(decision->reaction, IrReaction::kTurnLeft);
}

TEST(IrSafety, ReversingIntoABubbleSwingsTheRearAwayFromTheHits) {
  IrSafetyRun run;
  // Behind on the left (155 deg) at 0.4 m, inside its 0.54 m bubble at 0.5 m/s reversing.
  const msgs::IrRing rear_left = ring({{kRearLeft, 0.4}});
  run.step(rear_left, moving(-0.5));
  const auto decision = run.step(rear_left, moving(-0.5));
  ASSERT_TRUE(decision);
  EXPECT_EQ(decision->zone, IrZone::kBubble);
  // Turning left swings the rear to the right, away from the obstacle.
  EXPECT_EQ(decision->reaction, IrReaction::kTurnLeft);
}

TEST(IrSafety, TheTurnGivesUpAfterItsLongest) {
  IrSafetyRun run;
  const msgs::IrRing wall = ring({{kAhead, 0.5}});
  run.step(wall, moving(0.5));
  ASSERT_TRUE(run.step(wall, moving(0.5)));
  int ticks = 0;
  while (run.step(wall, {})) ASSERT_LT(++ticks, 1000);
  EXPECT_NEAR(ticks * kRing_s, 4.0, kRing_s + 1e-9);
}

TEST(IrSafety, UrgentWinsOverTheBubble) {
  IrSafetyRun run;
  const msgs::IrRing both = ring({{kAhead, 0.12}, {kLeft25, 0.5}});
  run.step(both, moving(0.5));
  const auto decision = run.step(both, moving(0.5));
  ASSERT_TRUE(decision);
  EXPECT_EQ(decision->zone, IrZone::kUrgent);
}

TEST(IrSafety, UnusableReadingsAreIgnored) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  IrSafetyRun run;
  for (const double bad : {nan, inf, -inf, -0.05, kNothing, 0.95}) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_FALSE(run.step(ring({{kAhead, bad}, {kLeft10, bad}}), moving(0.5))) << bad;
    }
  }
  msgs::IrRing broken_mount = ring({{kAhead, 0.12}});
  broken_mount.readings[kAhead].sensor_in_base.x = nan;
  for (int i = 0; i < 3; ++i) EXPECT_FALSE(run.step(broken_mount, moving(0.5)));
  for (int i = 0; i < 3; ++i) EXPECT_FALSE(run.step(msgs::IrRing{}, moving(0.5))) << "empty";
  // NaN speeds are no motion.
  for (int i = 0; i < 3; ++i) {
    EXPECT_FALSE(run.step(ring({{kAhead, 0.12}}), {{nan, 0.0}, {nan, 0.0}}));
  }
}

TEST(IrSafety, AStaleRingIsNotUsed) {
  IrSafetyRun run;
  const msgs::IrRing close = ring({{kAhead, 0.12}});
  run.step(close, moving(0.3));
  // No ring for 0.3 s: the confirmation starts over.
  EXPECT_FALSE(run.step_without_ring(moving(0.3), 0.3));
  EXPECT_FALSE(run.step(close, moving(0.3)));
  EXPECT_TRUE(run.step(close, moving(0.3)));
  // Between rings the reaction runs on.
  EXPECT_TRUE(run.step_without_ring(moving(0.3), 0.02));
}

TEST(IrSafety, ResetForgetsTheReaction) {
  IrSafetyRun run;
  const msgs::IrRing close = ring({{kAhead, 0.12}});
  run.step(close, moving(0.3));
  ASSERT_TRUE(run.step(close, moving(0.3)));
  run.safety().reset();
  EXPECT_FALSE(run.step(close, moving(0.3))) << "and the confirmations";
}

TEST(IrSafety, RejectsOptionsThatMakeNoSense) {
  const auto make = [](auto change) {
    IrSafetyOptions options;
    change(options);
    IrSafety safety(options);
  };
  EXPECT_THROW(make([](auto& o) { o.urgent_radius_m = -0.1; }), std::invalid_argument);
  EXPECT_THROW(make([](auto& o) { o.bubble_gain = std::nan(""); }), std::invalid_argument);
  EXPECT_THROW(make([](auto& o) { o.bubble_gains = {1.0, -2.0}; }), std::invalid_argument);
  EXPECT_THROW(make([](auto& o) { o.confirm_rings = 0; }), std::invalid_argument);
  EXPECT_THROW(make([](auto& o) { o.turn_max_s = std::numeric_limits<double>::infinity(); }),
               std::invalid_argument);
  EXPECT_NO_THROW(make([](auto&) {}));
}

}  // namespace
}  // namespace mobot::safety
