#include "api/prometheus_text.h"

#include <gtest/gtest.h>

namespace mobot::api {
namespace {

TEST(PrometheusText, WritesHelpTypeAndSample) {
  std::string out;
  append_metric(out, "mobot_ticks_total", "counter", "Ticks.", 42);
  EXPECT_EQ(out,
            "# HELP mobot_ticks_total Ticks.\n# TYPE mobot_ticks_total counter\n"
            "mobot_ticks_total 42\n");
}

TEST(PrometheusText, LabelsAndFurtherSamples) {
  std::string out;
  append_metric(out, "rate_hz", "gauge", "Rate.", 9.5, "sensor=\"laser\"");
  append_sample(out, "rate_hz", 50, "sensor=\"encoders\"");
  EXPECT_NE(out.find("rate_hz{sensor=\"laser\"} 9.5\n"), std::string::npos);
  EXPECT_NE(out.find("rate_hz{sensor=\"encoders\"} 50\n"), std::string::npos);
}

TEST(PrometheusText, SmallGaugesKeepTheirDigits) {
  std::string out;
  append_sample(out, "tick_seconds", 0.000123456, "");
  EXPECT_EQ(out, "tick_seconds 0.000123456\n");
}

}  // namespace
}  // namespace mobot::api
