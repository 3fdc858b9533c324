// The runtime: ticks run the stages in order on the robot clock; posted commands run between ticks
// and their replies see the state they produced.
#include "server/runtime.h"

#include <gtest/gtest.h>

namespace mobot::server {
namespace {

class RecordingStage final : public Stage {
 public:
  RecordingStage(std::string name, std::vector<std::string>& log)
      : name_(std::move(name)), log_(log) {}
  std::string_view name() const override { return name_; }
  void step(TickContext& context) override {
    log_.push_back(name_ + "@" + std::to_string(context.tick));
  }

 private:
  std::string name_;
  std::vector<std::string>& log_;
};

TEST(Runtime, TicksRunTheStagesInOrderOnAMonotonicClock) {
  Bus bus;
  std::vector<std::string> log;
  Pipeline pipeline;
  pipeline.add(std::make_unique<RecordingStage>("read", log));
  pipeline.add(std::make_unique<RecordingStage>("write", log));
  Runtime runtime(bus, std::move(pipeline), 0.02, RobotDescription{"differential", {}});
  EXPECT_EQ(runtime.stage_names(), (std::vector<std::string>{"read", "write"}));
  runtime.tick();
  runtime.tick();
  EXPECT_EQ(log, (std::vector<std::string>{"read@1", "write@1", "read@2", "write@2"}));
  EXPECT_NEAR(runtime.state()->robot.t_s, 0.04, 1e-12);
  EXPECT_NE(runtime.metrics_text().find("mobot_stage_seconds_mean{stage=\"read\"}"),
            std::string::npos);
}

TEST(Runtime, ACommandRunsBetweenTicksAndItsReplySeesTheStateItMade) {
  Bus bus;
  std::vector<std::string> log;
  Pipeline pipeline;
  pipeline.add(std::make_unique<RecordingStage>("stage", log));
  Runtime runtime(bus, std::move(pipeline), 0.02, RobotDescription{"differential", {}});
  int flushes = 0;
  bus.flush.subscribe([&](const TickEnd&) { ++flushes; });
  std::string mode_in_reply;
  runtime.post([&](TickContext& context) {
    log.emplace_back("command");
    context.navigating = true;
    context.then([&] { mode_in_reply = runtime.state()->robot.mode; });
  });
  runtime.tick();
  EXPECT_EQ(log, (std::vector<std::string>{"stage@1"})) << "posted, not run inline";
  runtime.run_posted();
  runtime.tick();
  EXPECT_EQ(log, (std::vector<std::string>{"stage@1", "command", "stage@2"}));
  EXPECT_EQ(mode_in_reply, "navigating");
  EXPECT_EQ(flushes, 3) << "each tick's and the command's publications are flushed at once";
}

TEST(Runtime, ATicksStreamBatchGoesOutAfterItsStateIsPublished) {
  Bus bus;
  std::vector<std::string> log;
  Pipeline pipeline;
  pipeline.add(std::make_unique<RecordingStage>("stage", log));
  Runtime runtime(bus, std::move(pipeline), 0.02, RobotDescription{"differential", {}});
  std::vector<double> state_t_at_flush;
  bus.flush.subscribe([&](const TickEnd& end) {
    EXPECT_NEAR(runtime.state()->robot.t_s, end.t_s, 1e-12) << "flushed before the state";
    state_t_at_flush.push_back(end.t_s);
  });
  runtime.tick();
  runtime.tick();
  EXPECT_EQ(state_t_at_flush.size(), 2U);
}

}  // namespace
}  // namespace mobot::server
