// What of a request may be logged (api/http_types.cpp): the target with its tokens redacted.
#include "api/http_types.h"

#include <gtest/gtest.h>

namespace mobot::api {
namespace {

TEST(RedactedTarget, ReplacesEveryTokenInTheQueryAndKeepsTheRest) {
  EXPECT_EQ(redacted_target("/api/v1/stream?token=abc123"), "/api/v1/stream?token=REDACTED");
  EXPECT_EQ(redacted_target("/api/v1/runs/1/trajectory?format=csv&token=s3cret&x=1"),
            "/api/v1/runs/1/trajectory?format=csv&token=REDACTED&x=1");
  EXPECT_EQ(redacted_target("/a?token=one&token=two"), "/a?token=REDACTED&token=REDACTED");
  EXPECT_EQ(redacted_target("/a?t%6Fken=encoded"), "/a?t%6Fken=REDACTED");
  EXPECT_EQ(redacted_target("/a?token"), "/a?token=REDACTED");
}

TEST(RedactedTarget, LeavesTargetsWithoutATokenAlone) {
  EXPECT_EQ(redacted_target("/api/v1/robot"), "/api/v1/robot");
  EXPECT_EQ(redacted_target("/api/v1/maps?tokens=3&mytoken=x"), "/api/v1/maps?tokens=3&mytoken=x");
  EXPECT_EQ(redacted_target("/?"), "/?");
  EXPECT_EQ(redacted_target("/a?&&"), "/a?&&");
}

}  // namespace
}  // namespace mobot::api
