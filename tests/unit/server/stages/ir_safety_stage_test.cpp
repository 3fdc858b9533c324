// The IR safety stage with fake drivers: its reactions drive the mux's ir_safety source over
// navigation, an urgent stop halts at once, each reaction is one event, and the source falls
// silent the tick a reaction ends.
#include "server/stages/ir_safety_stage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "server/stages/mux_stage.h"
#include "server/stages/read_drivers_stage.h"
#include "server/stages/smooth_stage.h"
#include "tests/unit/server/support/fake_drivers.h"

namespace mobot::server {
namespace {

using testing::FakeBase;
using testing::FakeSensor;

constexpr std::size_t kAhead = 3;

// The Dashgo's ten Sharp sensors (docs/algorithms.md R2); 0.8 m reads as nothing in range.
msgs::IrRing ring(const std::map<std::size_t, double>& ranges = {}) {
  constexpr double kBearingsDeg[] = {-45, -25, -10, 0, 10, 25, 45, 155, 180, 205};
  msgs::IrRing out;
  for (std::size_t i = 0; i < std::size(kBearingsDeg); ++i) {
    const double bearing = geometry::wrap_angle(kBearingsDeg[i] * std::numbers::pi / 180.0);
    const auto found = ranges.find(i);
    out.readings.push_back({{0.145 * std::cos(bearing), 0.145 * std::sin(bearing), bearing},
                            0.1,
                            0.10,
                            0.80,
                            found == ranges.end() ? 0.8 : found->second});
  }
  return out;
}

class IrSafetyPipeline : public ::testing::Test {
 protected:
  IrSafetyPipeline()
      : context_(bus_),
        read_(drivers_),
        ir_(
            {}, [this](const safety::IrSafetyDecision& d, TickContext&) { started_.push_back(d); },
            [this](const safety::IrSafetyDecision& d, TickContext&) { ended_.push_back(d); }),
        mux_({{"safety", 10, 0.2},
              {"ir_safety", 9, 0.5},
              {"teleop", 7, 1.0},
              {"navigation", 5, 1.0}}),
        smooth_({0.5, 0.7, 0.3, 0.3}) {
    drivers_.base = std::make_unique<FakeBase>();
    see(ring());
    bus_.events.subscribe([this](const EventSample& event) {
      if (event.kind == "ir_safety") events_.push_back(event.detail);
    });
  }

  void see(const msgs::IrRing& ir) {
    drivers_.ir = std::make_unique<FakeSensor<msgs::IrRing>>("ir", ir);
  }

  // One tick with navigation asking for `navigation_mps` and the odometry measuring `measured`.
  void tick(double navigation_mps, double measured_mps) {
    now_s_ += 0.02;
    context_.begin(now_s_, 0.02);
    read_.step(context_);
    context_.odometry.twist = {measured_mps, 0.0};
    context_.mux_requests.push_back({"navigation", msgs::Twist{navigation_mps, 0.0}});
    ir_.step(context_);
    mux_.step(context_);
    smooth_.step(context_);
  }

  Bus bus_;
  TickContext context_;
  drivers::DriverSet drivers_;
  ReadDriversStage read_;
  IrSafetyStage ir_;
  MuxStage mux_;
  SmoothStage smooth_;
  std::vector<nlohmann::json> events_;
  std::vector<safety::IrSafetyDecision> started_;
  std::vector<safety::IrSafetyDecision> ended_;
  double now_s_ = 0.0;
};

TEST_F(IrSafetyPipeline, AnUrgentObstacleHaltsBacksOffAndHandsBack) {
  for (int i = 0; i < 60; ++i) tick(0.3, context_.command.linear_mps);
  ASSERT_NEAR(context_.command.linear_mps, 0.3, 1e-9);
  EXPECT_EQ(context_.mux_source, "navigation");

  // 0.12 m from the front sensor: 0.265 m from the centre, inside the urgent zone.
  see(ring({{kAhead, 0.12}}));
  tick(0.3, 0.3);
  EXPECT_NEAR(context_.command.linear_mps, 0.3, 1e-9) << "one ring is not proof";
  tick(0.3, 0.3);
  EXPECT_DOUBLE_EQ(context_.command.linear_mps, 0.0) << "halted, no ramp";
  ASSERT_EQ(events_.size(), 1U);
  EXPECT_EQ(events_[0]["sensor"], kAhead);
  EXPECT_EQ(events_[0]["zone"], "urgent");
  EXPECT_EQ(events_[0]["reaction"], "stop");
  ASSERT_EQ(started_.size(), 1U);
  EXPECT_TRUE(started_[0].alarm);

  tick(0.3, 0.05);  // still rolling a little
  EXPECT_EQ(context_.mux_source, "ir_safety");
  EXPECT_DOUBLE_EQ(context_.command.linear_mps, 0.0);
  // Stopped: it backs off, ramping to -0.1 m/s.
  tick(0.3, 0.0);
  EXPECT_EQ(context_.mux_source, "ir_safety");
  EXPECT_LT(context_.command.linear_mps, 0.0);
  EXPECT_DOUBLE_EQ(context_.selected.linear_mps, -0.1);
  int ticks = 0;
  while (context_.mux_source == "ir_safety") {
    tick(0.3, context_.command.linear_mps);
    ASSERT_LT(++ticks, 500);
  }
  EXPECT_EQ(context_.mux_source, "navigation") << "at once, not after the 0.5 s time-out";
  EXPECT_EQ(events_.size(), 1U) << "one event for the whole reaction";
  ASSERT_EQ(ended_.size(), 1U);
  EXPECT_EQ(ended_[0].reaction, safety::IrReaction::kBackOff);
}

TEST_F(IrSafetyPipeline, ABubbleHitTurnsAwayThenEnds) {
  for (int i = 0; i < 60; ++i) tick(0.5, context_.command.linear_mps);
  // Two hits on the left at 0.5 m: inside the 0.6 m bubble at 0.5 m/s, outside the urgent zone.
  see(ring({{4, 0.5}, {5, 0.5}}));
  tick(0.5, 0.5);
  tick(0.5, 0.5);
  ASSERT_EQ(events_.size(), 1U);
  EXPECT_EQ(events_[0]["zone"], "bubble");
  EXPECT_EQ(events_[0]["reaction"], "turn_right");
  EXPECT_EQ(context_.mux_source, "ir_safety");
  EXPECT_DOUBLE_EQ(context_.selected.angular_radps, -0.4);
  EXPECT_GT(context_.command.linear_mps, 0.0) << "no halt: the smoother ramps the speed down";
  see(ring());
  tick(0.5, 0.4);
  EXPECT_EQ(context_.mux_source, "navigation");
  EXPECT_EQ(ended_.size(), 1U);
}

TEST_F(IrSafetyPipeline, NoRingNoEstopNoReaction) {
  drivers_.ir.reset();
  for (int i = 0; i < 20; ++i) tick(0.3, 0.3);
  EXPECT_EQ(context_.mux_source, "navigation");
  see(ring({{kAhead, 0.12}}));
  mux_.set_estop(true, context_);
  for (int i = 0; i < 20; ++i) tick(0.3, 0.3);
  EXPECT_TRUE(events_.empty()) << "under e-stop nothing reacts";
  EXPECT_TRUE(started_.empty());
}

TEST_F(IrSafetyPipeline, AStationaryBaseWithSomethingCloseIsLeftAlone) {
  see(ring({{kAhead, 0.10}, {8, 0.10}}));
  for (int i = 0; i < 20; ++i) tick(0.0, 0.0);
  EXPECT_TRUE(events_.empty());
  EXPECT_FALSE(context_.mux_source.has_value() && *context_.mux_source == "ir_safety");
}

}  // namespace
}  // namespace mobot::server
