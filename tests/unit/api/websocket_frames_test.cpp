#include "api/websocket_frames.h"

#include <gtest/gtest.h>

#include "client_frames.h"

namespace mobot::api {
namespace {

using test::client_frame;

TEST(WebSocketAcceptKey, MatchesRfc6455Example) {
  EXPECT_EQ(websocket_accept_key("dGhlIHNhbXBsZSBub25jZQ=="), "s3pPLMBiTxaQ9kYGzzhZRbK+xOo=");
}

TEST(EncodeWsFrame, UsesTheShortestLengthForm) {
  EXPECT_EQ(encode_ws_frame(WsOpcode::kText, "hi"), std::string("\x81\x02hi"));
  const std::string medium(300, 'x');
  const std::string frame = encode_ws_frame(WsOpcode::kBinary, medium);
  ASSERT_EQ(frame.size(), 4 + 300U);
  EXPECT_EQ(static_cast<unsigned char>(frame[1]), 126);
  EXPECT_EQ(static_cast<unsigned char>(frame[2]), 1);
  EXPECT_EQ(static_cast<unsigned char>(frame[3]), 44);
  const std::string large(70000, 'y');
  EXPECT_EQ(static_cast<unsigned char>(encode_ws_frame(WsOpcode::kBinary, large)[1]), 127);
}

TEST(WsFrameParser, UnmasksAndReassemblesAcrossFeeds) {
  WsFrameParser parser(1024);
  const std::string frame = client_frame(0x81, "{\"op\":\"ping\"}");
  parser.feed(frame.substr(0, 5));
  EXPECT_FALSE(parser.next().has_value());
  parser.feed(frame.substr(5));
  const auto message = parser.next();
  ASSERT_TRUE(message.has_value());
  EXPECT_EQ(message->opcode, WsOpcode::kText);
  EXPECT_EQ(message->payload, "{\"op\":\"ping\"}");
  EXPECT_FALSE(parser.failed());
}

TEST(WsFrameParser, JoinsFragmentsAndPassesInterleavedControlFrames) {
  WsFrameParser parser(1024);
  parser.feed(client_frame(0x01, "hel"));
  parser.feed(client_frame(0x89, "p"));
  parser.feed(client_frame(0x80, "lo"));
  const auto ping = parser.next();
  ASSERT_TRUE(ping.has_value());
  EXPECT_EQ(ping->opcode, WsOpcode::kPing);
  const auto text = parser.next();
  ASSERT_TRUE(text.has_value());
  EXPECT_EQ(text->payload, "hello");
}

TEST(WsFrameParser, RejectsUnmaskedFrames) {
  WsFrameParser parser(1024);
  parser.feed(std::string("\x81\x02hi"));
  EXPECT_FALSE(parser.next().has_value());
  EXPECT_EQ(parser.error_code(), 1002);
}

TEST(WsFrameParser, RejectsOversizedMessages) {
  WsFrameParser parser(100);
  parser.feed(client_frame(0x81, std::string(200, 'a')));
  EXPECT_FALSE(parser.next().has_value());
  EXPECT_EQ(parser.error_code(), 1009);
}

TEST(WsFrameParser, RejectsReservedBitsAndUnknownOpcodes) {
  WsFrameParser reserved(100);
  reserved.feed(client_frame(0xC1, "x"));
  EXPECT_FALSE(reserved.next().has_value());
  EXPECT_EQ(reserved.error_code(), 1002);
  WsFrameParser unknown(100);
  unknown.feed(client_frame(0x83, "x"));
  EXPECT_FALSE(unknown.next().has_value());
  EXPECT_EQ(unknown.error_code(), 1002);
}

TEST(WsFrameParser, RejectsContinuationWithoutStart) {
  WsFrameParser parser(100);
  parser.feed(client_frame(0x80, "x"));
  EXPECT_FALSE(parser.next().has_value());
  EXPECT_TRUE(parser.failed());
}

}  // namespace
}  // namespace mobot::api
