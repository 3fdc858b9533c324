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

namespace mobot::api {
namespace {

TEST(PrometheusLabel, UserTextIsEscaped) {
  EXPECT_EQ(label("label", "alice"), R"(label="alice")");
  EXPECT_EQ(label("label", "a\"b\\c\nd"), R"(label="a\"b\\c\nd")");
  EXPECT_EQ(label("label", ""), R"(label="")");
}

TEST(PrometheusLabel, HistogramBoundsInTheirShortestForm) {
  EXPECT_EQ(prometheus_number(0.001), "0.001");
  EXPECT_EQ(prometheus_number(0.5), "0.5");
  EXPECT_EQ(prometheus_number(2.0), "2");
}

}  // namespace
}  // namespace mobot::api
