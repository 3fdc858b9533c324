// The sonar safety stage with fake drivers: R2's emergency rules through the mux's safety source,
// a stop halts at once, one event per episode, and the shared source is never cleared from here.
#include "server/stages/sonar_safety_stage.h"

#include <gtest/gtest.h>

#include <numbers>

#include "server/stages/mux_stage.h"
#include "server/stages/read_drivers_stage.h"
#include "server/stages/smooth_stage.h"
#include "tests/unit/server/support/fake_drivers.h"

namespace mobot::server {
namespace {

using testing::FakeBase;
using testing::FakeSensor;

// The Dashgo's four sonars (docs/algorithms.md R2); 0.8 m is no echo.
msgs::SonarRing sonars(double s0, double s1, double s2, double s3) {
  const geometry::Pose2D mounts[] = {{0.18, 0.10, std::numbers::pi / 6},
                                     {0.20, 0.0, 0.0},
                                     {0.18, -0.10, -std::numbers::pi / 6},
                                     {-0.20, 0.0, std::numbers::pi}};
  const double ranges[] = {s0, s1, s2, s3};
  msgs::SonarRing out;
  for (int i = 0; i < 4; ++i) out.readings.push_back({mounts[i], 0.3, 0.03, 0.8, ranges[i]});
  return out;
}

class SonarSafetyPipeline : public ::testing::Test {
 protected:
  SonarSafetyPipeline()
      : context_(bus_),
        read_(drivers_),
        mux_({{"safety", 10, 0.2},
              {"ir_safety", 9, 0.5},
              {"teleop", 7, 1.0},
              {"navigation", 5, 1.0}}),
        smooth_({0.5, 0.7, 0.3, 0.3}) {
    drivers_.base = std::make_unique<FakeBase>();
    hear(sonars(0.8, 0.8, 0.8, 0.8));
    bus_.events.subscribe([this](const EventSample& event) {
      if (event.kind == "sonar_safety") events_.push_back(event.detail);
    });
  }

  void hear(const msgs::SonarRing& ring) {
    drivers_.sonar = std::make_unique<FakeSensor<msgs::SonarRing>>("sonar", ring);
  }
  FakeSensor<msgs::SonarRing>& sonar() {
    return static_cast<FakeSensor<msgs::SonarRing>&>(*drivers_.sonar);
  }

  void tick(double navigation_mps, double measured_mps) {
    now_s_ += 0.02;
    context_.begin(now_s_, 0.02);
    read_.step(context_);
    context_.odometry.twist = {measured_mps, 0.0};
    context_.mux_requests.push_back({"navigation", msgs::Twist{navigation_mps, 0.0}});
    sonar_.step(context_);
    for (const auto& request : context_.mux_requests) {
      if (request.source == "safety") {
        EXPECT_TRUE(request.command) << "never cleared from here";
      }
    }
    mux_.step(context_);
    smooth_.step(context_);
  }

  Bus bus_;
  TickContext context_;
  drivers::DriverSet drivers_;
  ReadDriversStage read_;
  SonarSafetyStage sonar_;
  MuxStage mux_;
  SmoothStage smooth_;
  std::vector<nlohmann::json> events_;
  double now_s_ = 0.0;
};

TEST_F(SonarSafetyPipeline, SomethingAtTheFrontSonarStopsAtOnceAsOneEvent) {
  for (int i = 0; i < 60; ++i) tick(0.3, context_.command.linear_mps);
  ASSERT_NEAR(context_.command.linear_mps, 0.3, 1e-9);
  hear(sonars(0.8, 0.05, 0.8, 0.8));
  tick(0.3, 0.3);
  EXPECT_DOUBLE_EQ(context_.command.linear_mps, 0.0) << "halted, no ramp";
  ASSERT_EQ(events_.size(), 1U);
  EXPECT_EQ(events_[0]["sensor"], 1);
  EXPECT_EQ(events_[0]["zone"], "front_stop");
  EXPECT_EQ(events_[0]["reaction"], "stop");
  // Navigation pushes on: the rule keeps the base where it is, and it is one episode.
  for (int i = 0; i < 100; ++i) tick(0.3, context_.command.linear_mps);
  EXPECT_LT(context_.command.linear_mps, 0.02);
  EXPECT_EQ(events_.size(), 1U);
  // The obstacle goes: the safety source lapses within its 0.2 s and navigation drives again.
  hear(sonars(0.8, 0.8, 0.8, 0.8));
  for (int i = 0; i < 11; ++i) tick(0.3, context_.command.linear_mps);
  for (int i = 0; i < 30; ++i) {
    tick(0.3, context_.command.linear_mps);
    EXPECT_EQ(context_.mux_source, "navigation");
  }
  EXPECT_GT(context_.command.linear_mps, 0.1);
}

TEST_F(SonarSafetyPipeline, ASideSonarTurnsAway) {
  for (int i = 0; i < 30; ++i) tick(0.3, context_.command.linear_mps);
  hear(sonars(0.08, 0.8, 0.8, 0.8));
  tick(0.3, 0.3);
  EXPECT_EQ(context_.mux_source, "safety");
  EXPECT_EQ(context_.selected, (msgs::Twist{0.0, -0.2}));
  ASSERT_EQ(events_.size(), 1U);
  EXPECT_EQ(events_[0]["zone"], "turn_right");
  EXPECT_EQ(events_[0]["reaction"], "turn_right");
  EXPECT_GT(context_.command.linear_mps, 0.0) << "a turn is no halt: the speed ramps down";
}

TEST_F(SonarSafetyPipeline, ASilentSonarOrAStillBaseFiresNothing) {
  hear(sonars(0.03, 0.03, 0.03, 0.03));
  for (int i = 0; i < 20; ++i) tick(0.0, 0.0);
  EXPECT_TRUE(events_.empty()) << "standing still";
  // Told to go: the rules judge the command the base was given last tick, so the first tick of
  // motion fires.
  tick(0.3, 0.0);
  EXPECT_TRUE(events_.empty());
  tick(0.3, 0.0);
  EXPECT_EQ(events_.size(), 1U);
  // The sonar falls silent: its last ring counts for 0.3 s, then nothing fires.
  sonar().silent = true;
  for (int i = 0; i < 16; ++i) tick(0.3, 0.3);
  EXPECT_FALSE(sonar_.active());
  for (int i = 0; i < 15; ++i) tick(0.3, context_.command.linear_mps);
  EXPECT_EQ(context_.mux_source, "navigation");
}

TEST_F(SonarSafetyPipeline, AReversingBaseStopsForTheRearSonarOnly) {
  hear(sonars(0.8, 0.8, 0.8, 0.05));
  for (int i = 0; i < 10; ++i) tick(0.3, 0.3);
  EXPECT_TRUE(events_.empty());
  tick(-0.2, -0.2);
  ASSERT_EQ(events_.size(), 1U);
  EXPECT_EQ(events_[0]["zone"], "rear_stop");
  EXPECT_EQ(events_[0]["sensor"], 3);
}

}  // namespace
}  // namespace mobot::server
