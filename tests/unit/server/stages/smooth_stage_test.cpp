// The smooth stage ramps with the acceleration limits, and drops the ramp when the commands were
// dropped (an e-stop or a reset between two ticks, a contact within one).
#include "server/stages/smooth_stage.h"

#include <gtest/gtest.h>

#include "server/stages/mux_stage.h"

namespace mobot::server {
namespace {

TEST(SmoothStage, RampsAndStopsAtOnceWhenTheCommandsWereDropped) {
  Bus bus;
  TickContext context(bus);
  control::VelocityLimits limits;
  limits.max_linear_accel_mps2 = 1.0;
  SmoothStage smooth(limits);
  MuxStage mux({{"safety", 10, 0.2}, {"teleop", 7, 1.0}});
  double now_s = 0.0;
  const auto tick = [&] {
    now_s += 0.02;
    context.begin(now_s, 0.02);
    mux.step(context);
    smooth.step(context);
  };
  mux.submit_teleop({0.5, 0.0}, 1.0, context);
  tick();
  EXPECT_NEAR(context.command.linear_mps, 0.02, 1e-9) << "1 m/s^2 for one 20 ms tick";
  for (int i = 0; i < 30; ++i) tick();
  EXPECT_NEAR(context.command.linear_mps, 0.5, 1e-9);

  // A command between ticks (a sim reset) drops everything; a teleop right after it survives.
  mux.drop_commands(context);
  tick();
  EXPECT_DOUBLE_EQ(context.command.linear_mps, 0.0) << "no ramp down after dropped commands";
  mux.drop_commands(context);
  mux.submit_teleop({0.5, 0.0}, 1.0, context);
  tick();
  EXPECT_NEAR(context.command.linear_mps, 0.0, 1e-9) << "the halt is taken once, then the ramp";
  tick();
  EXPECT_NEAR(context.command.linear_mps, 0.02, 1e-9);
  EXPECT_EQ(context.mux_source, "teleop") << "a command after the drop is not lost";
}

}  // namespace
}  // namespace mobot::server
