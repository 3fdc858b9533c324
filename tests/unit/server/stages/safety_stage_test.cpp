// The safety layer with fake drivers: a required sensor that falls silent or reports a fault stops
// the robot through the mux's safety source; a contact halts at once; each fault is one event.
#include "server/stages/safety_stage.h"

#include <gtest/gtest.h>

#include "core/kinematics/differential_model.h"
#include "server/stages/mux_stage.h"
#include "server/stages/read_drivers_stage.h"
#include "server/stages/smooth_stage.h"
#include "server/stages/write_base_stage.h"
#include "tests/unit/server/support/fake_drivers.h"

namespace mobot::server {
namespace {

using testing::FakeBase;
using testing::FakeSensor;

class SafetyPipeline : public ::testing::Test {
 protected:
  SafetyPipeline()
      : context_(bus_),
        model_({0.1, 0.5, {}}),
        read_(drivers_),
        safety_(
            {{"encoders", 0.5, true}, {"laser", 0.5, true}, {"sonar", 0.5, false}},
            [this](const std::string& reason, TickContext&) { ended_goals_.push_back(reason); }),
        mux_({{"safety", 10, 0.2}, {"teleop", 7, 1.0}, {"navigation", 5, 1.0}}),
        smooth_(limits()),
        write_(base(), model_) {
    bus_.events.subscribe([this](const EventSample& event) { events_.push_back(event); });
  }

  static control::VelocityLimits limits() {
    control::VelocityLimits limits;
    limits.max_linear_accel_mps2 = 100.0;  // no ramp: the tests look at the command itself
    limits.max_angular_accel_radps2 = 100.0;
    return limits;
  }

  FakeBase& base() {
    if (!drivers_.base) {
      drivers_.base = std::make_unique<FakeBase>();
      drivers_.laser = std::make_unique<FakeSensor<msgs::LaserScan>>("laser", msgs::LaserScan{});
      drivers_.sonar = std::make_unique<FakeSensor<msgs::SonarRing>>("sonar", msgs::SonarRing{});
    }
    return static_cast<FakeBase&>(*drivers_.base);
  }
  FakeSensor<msgs::LaserScan>& laser() {
    return static_cast<FakeSensor<msgs::LaserScan>&>(*drivers_.laser);
  }

  // One tick with navigation asking for 0.5 m/s.
  void tick() {
    now_s_ += 0.02;
    context_.begin(now_s_, 0.02);
    read_.step(context_);
    context_.mux_requests.push_back({"navigation", msgs::Twist{0.5, 0.0}});
    safety_.step(context_);
    mux_.step(context_);
    smooth_.step(context_);
    write_.step(context_);
  }
  double commanded_linear_mps() const {
    return model_.to_body(static_cast<FakeBase&>(*drivers_.base).commands.back()).linear_mps;
  }
  int events_of(const std::string& kind) const {
    return static_cast<int>(std::count_if(events_.begin(), events_.end(),
                                          [&](const EventSample& e) { return e.kind == kind; }));
  }

  Bus bus_;
  TickContext context_;
  drivers::DriverSet drivers_;
  kinematics::DifferentialModel model_;
  ReadDriversStage read_;
  SafetyStage safety_;
  MuxStage mux_;
  SmoothStage smooth_;
  WriteBaseStage write_;
  std::vector<std::string> ended_goals_;
  std::vector<EventSample> events_;
  double now_s_ = 0.0;
};

TEST_F(SafetyPipeline, AStaleLaserStopsTheRobotThroughTheSafetySource) {
  for (int i = 0; i < 10; ++i) tick();
  EXPECT_NEAR(commanded_linear_mps(), 0.5, 1e-9);
  EXPECT_TRUE(context_.faults.empty());

  laser().silent = true;
  for (int i = 0; i < 30; ++i) tick();  // 0.6 s: past the 0.5 s time-out
  EXPECT_EQ(context_.faults, std::vector<std::string>{"laser"});
  EXPECT_EQ(context_.mux_source, "safety");
  EXPECT_DOUBLE_EQ(commanded_linear_mps(), 0.0);
  EXPECT_EQ(events_of("fault"), 1) << "one event when the fault starts, not one per tick";
  EXPECT_EQ(ended_goals_, std::vector<std::string>{"sensor_fault"});

  laser().silent = false;
  for (int i = 0; i < 20; ++i) tick();  // the safety command times out after 0.2 s
  EXPECT_TRUE(context_.faults.empty());
  EXPECT_NEAR(commanded_linear_mps(), 0.5, 1e-9);
}

TEST_F(SafetyPipeline, ADriverFaultStopsTheRobotAndNamesTheReason) {
  for (int i = 0; i < 5; ++i) tick();
  laser().device_status = {false, "checksum"};
  tick();
  EXPECT_DOUBLE_EQ(commanded_linear_mps(), 0.0);
  const auto laser_state = std::find_if(context_.sensors.begin(), context_.sensors.end(),
                                        [](const SensorState& s) { return s.name == "laser"; });
  ASSERT_NE(laser_state, context_.sensors.end());
  EXPECT_FALSE(laser_state->ok);
  EXPECT_EQ(laser_state->reason, "checksum");
  ASSERT_EQ(events_of("fault"), 1);
  EXPECT_EQ(events_.back().detail["reason"], "checksum");
}

TEST_F(SafetyPipeline, AnOptionalSensorsSilenceDoesNotStopTheRobot) {
  static_cast<FakeSensor<msgs::SonarRing>&>(*drivers_.sonar).silent = true;
  for (int i = 0; i < 40; ++i) tick();
  EXPECT_TRUE(context_.faults.empty());
  EXPECT_NEAR(commanded_linear_mps(), 0.5, 1e-9);
  const auto sonar = std::find_if(context_.sensors.begin(), context_.sensors.end(),
                                  [](const SensorState& s) { return s.name == "sonar"; });
  EXPECT_FALSE(sonar->ok);
}

TEST_F(SafetyPipeline, AContactHaltsAtOnceAndFailsTheGoal) {
  for (int i = 0; i < 5; ++i) tick();
  base().contacts.push_back({0.1, "wall", {1.0, 2.0, 0.0}});
  tick();
  EXPECT_DOUBLE_EQ(commanded_linear_mps(), 0.0) << "no ramp down: the base stops where it is";
  EXPECT_EQ(ended_goals_, std::vector<std::string>{"collision"});
  EXPECT_EQ(events_of("collision"), 1);
  EXPECT_EQ(safety_.contacts(), 1U);
}

}  // namespace
}  // namespace mobot::server
