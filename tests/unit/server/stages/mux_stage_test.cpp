// The mux stage: priorities and time-outs, e-stop over everything, teleop lapses as events.
#include "server/stages/mux_stage.h"

#include <gtest/gtest.h>

namespace mobot::server {
namespace {

class MuxStageTest : public ::testing::Test {
 protected:
  MuxStageTest()
      : context_(bus_), mux_({{"safety", 10, 0.2}, {"teleop", 7, 1.0}, {"navigation", 5, 1.0}}) {
    bus_.events.subscribe([this](const EventSample& event) { events_.push_back(event.kind); });
  }

  void tick(std::vector<MuxRequest> requests = {}) {
    now_s_ += 0.02;
    context_.begin(now_s_, 0.02);
    context_.mux_requests = std::move(requests);
    mux_.step(context_);
  }

  Bus bus_;
  TickContext context_;
  MuxStage mux_;
  std::vector<std::string> events_;
  double now_s_ = 0.0;
};

TEST_F(MuxStageTest, TheHighestPrioritySourceThatSpokeDrives) {
  tick({{"navigation", msgs::Twist{0.3, 0.0}}});
  EXPECT_EQ(context_.mux_source, "navigation");
  mux_.submit_teleop({0.1, 0.2}, 0.3, context_);
  tick({{"navigation", msgs::Twist{0.3, 0.0}}});
  EXPECT_EQ(context_.mux_source, "teleop");
  EXPECT_DOUBLE_EQ(context_.selected.angular_radps, 0.2);
  EXPECT_TRUE(context_.teleop_active);
  tick({{"safety", msgs::Twist{}}, {"navigation", msgs::Twist{0.3, 0.0}}});
  EXPECT_EQ(context_.mux_source, "safety");
  EXPECT_DOUBLE_EQ(context_.selected.linear_mps, 0.0);
}

TEST_F(MuxStageTest, ASourceFallsSilentAfterItsTimeOutAndALapsedTeleopIsAnEvent) {
  mux_.submit_teleop({0.4, 0.0}, 0.1, context_);  // ttl 0.1 s
  tick();
  EXPECT_EQ(context_.mux_source, "teleop");
  for (int i = 0; i < 6; ++i) tick();  // 0.14 s
  EXPECT_FALSE(context_.mux_source.has_value()) << "every source silent: the base stops";
  EXPECT_DOUBLE_EQ(context_.selected.linear_mps, 0.0);
  EXPECT_EQ(std::count(events_.begin(), events_.end(), "teleop_timeout"), 1);
}

TEST_F(MuxStageTest, EstopWinsOverEverySourceAndDropsPendingCommands) {
  mux_.submit_teleop({0.4, 0.0}, 1.0, context_);
  EXPECT_TRUE(mux_.set_estop(true, context_));
  tick({{"navigation", msgs::Twist{0.3, 0.0}}});
  EXPECT_TRUE(context_.estop);
  EXPECT_DOUBLE_EQ(context_.selected.linear_mps, 0.0);
  EXPECT_FALSE(mux_.set_estop(false, context_));
  tick();
  EXPECT_FALSE(context_.mux_source.has_value()) << "the teleop command was dropped, not paused";
  EXPECT_EQ(std::count(events_.begin(), events_.end(), "estop"), 2);
  EXPECT_EQ(std::count(events_.begin(), events_.end(), "teleop_timeout"), 0)
      << "a command dropped on purpose did not time out";
  EXPECT_FALSE(mux_.set_estop(false, context_));
  EXPECT_EQ(std::count(events_.begin(), events_.end(), "estop"), 2) << "no change, no event";
}

TEST_F(MuxStageTest, ARequestWithoutACommandSilencesItsSourceAtOnce) {
  tick({{"navigation", msgs::Twist{0.3, 0.0}}});
  tick({{"navigation", std::nullopt}});
  EXPECT_FALSE(context_.mux_source.has_value());
}

}  // namespace
}  // namespace mobot::server
