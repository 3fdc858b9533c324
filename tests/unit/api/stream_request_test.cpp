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
  const auto teleop = std::get<StreamTeleopRequest>(
      parse_stream_request(R"({"op":"teleop","v":0.5,"w":-0.25,"ttl_ms":120})", Role::kOperator));
  EXPECT_DOUBLE_EQ(teleop.command.twist.linear_mps, 0.5);
  EXPECT_DOUBLE_EQ(teleop.command.twist.angular_radps, -0.25);
  EXPECT_EQ(teleop.command.ttl_ms, 120);
  EXPECT_FALSE(teleop.seq.has_value());
  EXPECT_FALSE(teleop.sent_ms.has_value());
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

TEST(StreamRequest, ATeleopLeaseCarriesItsSequenceAndSendTime) {
  const auto teleop = std::get<StreamTeleopRequest>(parse_stream_request(
      R"({"op":"teleop","v":0.2,"w":0,"ttl_ms":300,"seq":9007199254740991,"sent_ms":1733380000123.5})",
      Role::kOperator));
  EXPECT_EQ(teleop.seq, 9007199254740991ULL);
  EXPECT_DOUBLE_EQ(*teleop.sent_ms, 1733380000123.5);
  EXPECT_EQ(std::get<StreamTeleopRequest>(
                parse_stream_request(R"({"op":"teleop","v":0,"w":0,"seq":0})", Role::kOperator))
                .seq,
            0U);
  // Beyond what a JavaScript number holds exactly, negative, fractional, a string: refused.
  for (const char* seq : {"9007199254740992", "-1", "1.5", "\"3\"", "null", "1e300"}) {
    EXPECT_EQ(error_code(std::string(R"({"op":"teleop","v":0,"w":0,"seq":)") + seq + "}"),
              "invalid_field")
        << seq;
  }
  for (const char* sent : {"-1", "\"now\"", "1e300"}) {
    EXPECT_NE(error_code(std::string(R"({"op":"teleop","v":0,"w":0,"sent_ms":)") + sent + "}"),
              "accepted")
        << sent;
  }
}

TEST(StreamRequest, AnEstopNeedsTheOperatorRoleAndSaysWhichWay) {
  EXPECT_TRUE(std::get<EstopRequest>(
                  parse_stream_request(R"({"op":"estop","engaged":true})", Role::kOperator))
                  .engaged);
  EXPECT_FALSE(std::get<EstopRequest>(
                   parse_stream_request(R"({"op":"estop","engaged":false})", Role::kAdmin))
                   .engaged);
  EXPECT_EQ(error_code(R"({"op":"estop","engaged":true})", Role::kViewer), "forbidden");
  EXPECT_EQ(error_code(R"({"op":"estop"})"), "missing_field");
  EXPECT_EQ(error_code(R"({"op":"estop","engaged":1})"), "invalid_field");
}

}  // namespace
}  // namespace mobot::api
