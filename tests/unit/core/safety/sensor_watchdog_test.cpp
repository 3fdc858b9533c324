#include "core/safety/sensor_watchdog.h"

#include <gtest/gtest.h>

namespace mobot::safety {
namespace {

TEST(SensorWatchdog, MeasuresRateOverTheLastSecond) {
  SensorWatchdog watchdog;
  watchdog.add("laser", 0.5, true);
  for (int i = 0; i <= 20; ++i) watchdog.seen("laser", i * 0.1);
  const auto status = watchdog.status(2.0);
  ASSERT_EQ(status.size(), 1U);
  EXPECT_TRUE(status[0].ok);
  EXPECT_NEAR(status[0].rate_hz, 10.0, 1.0);
}

TEST(SensorWatchdog, SilentRequiredSensorIsStale) {
  SensorWatchdog watchdog;
  watchdog.add("laser", 0.5, true);
  watchdog.add("sonar", 0.5, false);
  watchdog.seen("laser", 0.0);
  watchdog.seen("sonar", 0.0);
  EXPECT_TRUE(watchdog.stale_required(0.4).empty());
  const auto stale = watchdog.stale_required(0.6);
  ASSERT_EQ(stale.size(), 1U);
  EXPECT_EQ(stale[0], "laser");
  EXPECT_FALSE(watchdog.status(0.6)[1].ok);
}

TEST(SensorWatchdog, NeverSeenSensorGetsOneTimeoutOfGrace) {
  SensorWatchdog watchdog;
  watchdog.add("laser", 0.5, true);
  watchdog.add("encoders", 0.5, true);
  watchdog.seen("encoders", 0.0);
  EXPECT_TRUE(watchdog.stale_required(0.3).empty());
  watchdog.seen("encoders", 0.6);
  EXPECT_EQ(watchdog.stale_required(0.6), std::vector<std::string>{"laser"});
}

}  // namespace
}  // namespace mobot::safety
