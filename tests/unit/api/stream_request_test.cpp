// A stream client's ops parsed before the session acts on them (api/stream_request.cpp), with
// the error codes the session answers.
#include "api/stream_request.h"

#include <gtest/gtest.h>

#include <string>
#include <variant>

#include "api/api_error.h"

namespace mobot::api {
namespace {

std::string error_code(const std::string& text, Role role = Role::kOperator) {
  try {
    parse_stream_request(text, role);
  } catch (const ApiError& error) {
    return error.code();
  }
  return "accepted";
}

TEST(StreamRequest, ParsesASubscriptionWithItsOptions) {
  const StreamRequest request = parse_stream_request(
      R"({"op":"subscribe","topics":["pose","camera"],"encoding":"json","max_rate_hz":4,)"
      R"("camera_quality":30})",
      Role::kViewer);
  const auto& subscribe = std::get<SubscribeRequest>(request);
  EXPECT_EQ(subscribe.topics, (std::vector<std::string>{"pose", "camera"}));
  EXPECT_FALSE(subscribe.binary);
  EXPECT_EQ(subscribe.min_interval_us, 250'000);
  EXPECT_EQ(subscribe.camera_quality, 30);
  const StreamRequest plain =
      parse_stream_request(R"({"op":"subscribe","topics":[]})", Role::kViewer);
  const auto& defaults = std::get<SubscribeRequest>(plain);
  EXPECT_TRUE(defaults.binary);
  EXPECT_EQ(defaults.min_interval_us, 0);
  EXPECT_EQ(defaults.camera_quality, 0);
}

TEST(StreamRequest, ParsesUnsubscribeTeleopAndPing) {
  EXPECT_EQ(std::get<UnsubscribeRequest>(
                parse_stream_request(R"({"op":"unsubscribe","topics":["map"]})", Role::kViewer))
                .topics,
            std::vector<std::string>{"map"});
  const auto teleop = std::get<TeleopRequest>(
      parse_stream_request(R"({"op":"teleop","v":0.5,"w":-0.25,"ttl_ms":120})", Role::kOperator));
  EXPECT_DOUBLE_EQ(teleop.twist.linear_mps, 0.5);
  EXPECT_DOUBLE_EQ(teleop.twist.angular_radps, -0.25);
  EXPECT_EQ(teleop.ttl_ms, 120);
  EXPECT_EQ(
      std::get<PingRequest>(parse_stream_request(R"({"op":"ping","id":"a"})", Role::kViewer)).id,
      "a");
  EXPECT_TRUE(
      std::get<PingRequest>(parse_stream_request(R"({"op":"ping"})", Role::kViewer)).id.is_null());
}

TEST(StreamRequest, RefusesWithTheCodesTheSessionAnswers) {
  EXPECT_EQ(error_code("{"), "malformed_json");
  EXPECT_EQ(error_code(R"({"v":1e999})"), "malformed_json");
  EXPECT_EQ(error_code("[]"), "missing_op");
  EXPECT_EQ(error_code(R"({"op":3})"), "missing_op");
  EXPECT_EQ(error_code(R"({"op":"dance"})"), "unknown_op");
  EXPECT_EQ(error_code(R"({"op":"subscribe"})"), "invalid_topics");
  EXPECT_EQ(error_code(R"({"op":"unsubscribe","topics":[1]})"), "invalid_topics");
  EXPECT_EQ(error_code(R"({"op":"subscribe","topics":[],"encoding":"xml"})"), "invalid_encoding");
  EXPECT_EQ(error_code(R"({"op":"subscribe","topics":[],"max_rate_hz":0})"), "invalid_field");
  EXPECT_EQ(error_code(R"({"op":"subscribe","topics":[],"camera_quality":50.5})"), "invalid_field");
  EXPECT_EQ(error_code(R"({"op":"teleop","v":0.5})"), "missing_field");
  EXPECT_EQ(error_code(R"({"op":"teleop","v":500,"w":0})"), "invalid_field");
}

TEST(StreamRequest, ATeleopFromAViewerIsForbiddenBeforeItsFieldsAreRead) {
  EXPECT_EQ(error_code(R"({"op":"teleop"})", Role::kViewer), "forbidden");
  EXPECT_EQ(error_code(R"({"op":"teleop","v":0.1,"w":0})", Role::kViewer), "forbidden");
  EXPECT_EQ(error_code(R"({"op":"teleop","v":0.1,"w":0})", Role::kAdmin), "accepted");
}

}  // namespace
}  // namespace mobot::api
