#include "core/timing/rate_schedule.h"

#include <gtest/gtest.h>

#include <vector>

namespace mobot::timing {
namespace {

std::vector<double> readings(RateSchedule schedule, double tick_s, int ticks) {
  std::vector<double> taken;
  double now_s = 0.0;
  for (int i = 0; i < ticks; ++i) {
    now_s += tick_s;
    if (schedule.due(now_s)) {
      schedule.taken(now_s);
      taken.push_back(now_s);
    }
  }
  return taken;
}

TEST(RateSchedule, ReadingsAreExactlyOnePeriodApartFromTheFirst) {
  const auto taken = readings(RateSchedule(0.1), 0.02, 500);
  ASSERT_EQ(taken.size(), 100U);
  for (std::size_t i = 1; i < taken.size(); ++i) EXPECT_NEAR(taken[i] - taken[i - 1], 0.1, 1e-9);
}

TEST(RateSchedule, ARateThatIsNotAMultipleOfTheTickKeepsItsAverage) {
  const auto taken = readings(RateSchedule(1.0 / 30.0), 0.02, 5000);  // 100 s
  EXPECT_NEAR(static_cast<double>(taken.size()), 3000.0, 1.0);
}

TEST(RateSchedule, AMissedReadingReanchorsInsteadOfBursting) {
  RateSchedule schedule(0.1);
  schedule.taken(0.0);
  EXPECT_FALSE(schedule.due(0.05));
  EXPECT_TRUE(schedule.due(0.1));
  schedule.taken(0.75);  // the loop stalled
  EXPECT_FALSE(schedule.due(0.8));
  EXPECT_TRUE(schedule.due(0.85));
}

}  // namespace
}  // namespace mobot::timing
