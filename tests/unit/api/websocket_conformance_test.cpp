// RFC 6455 sections 5 and 7 against our own framing, in the order of the Autobahn TestSuite's
// cases (numbers in the comments): first the client frame parser alone, then the close handshake
// and the close codes the server sends, through a real StreamSession over loopback.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "api/utf8_validator.h"
#include "api/websocket_frames.h"
#include "stream_session_harness.h"

namespace mobot::api {
namespace {

using namespace std::chrono_literals;
using test::client_frame;
using test::close_payload;
using test::Frame;

constexpr unsigned kFin = 0x80;
constexpr unsigned kContinuation = 0x0;
constexpr unsigned kText = 0x1;
constexpr unsigned kBinary = 0x2;
constexpr unsigned kClose = 0x8;
constexpr unsigned kPing = 0x9;
constexpr unsigned kPong = 0xA;

constexpr std::uint16_t kProtocolError = 1002;
constexpr std::uint16_t kInvalidPayload = 1007;
constexpr std::uint16_t kMessageTooBig = 1009;

struct Parsed {
  std::vector<WsMessage> messages;
  std::uint16_t error = 0;
};

// Everything a parser makes of `bytes`, fed `chunk` bytes at a time (0: all at once) with the
// messages taken after each feed, as the session does.
Parsed parse(std::string_view bytes, std::size_t limit = 1 << 20, std::size_t chunk = 0) {
  WsFrameParser parser(limit);
  Parsed parsed;
  const std::size_t step = chunk == 0 ? std::max<std::size_t>(bytes.size(), 1) : chunk;
  for (std::size_t at = 0; at < bytes.size(); at += step) {
    parser.feed(bytes.substr(at, step));
    while (auto message = parser.next()) parsed.messages.push_back(std::move(*message));
  }
  parsed.error = parser.error_code();
  return parsed;
}

std::string repeat(std::string_view text, std::size_t times) {
  std::string out;
  for (std::size_t i = 0; i < times; ++i) out.append(text);
  return out;
}

// ---- 1.x: payload lengths in each length form ---------------------------------------------------

TEST(WsConformance, Case1_DataMessagesOfEveryLengthFormArriveWhole) {
  for (const std::size_t length : {0UL, 125UL, 126UL, 127UL, 128UL, 65535UL, 65536UL, 100000UL}) {
    for (const unsigned opcode : {kText, kBinary}) {
      const std::string payload(length, '*');
      for (const std::size_t chunk : {0UL, 997UL}) {
        const Parsed parsed = parse(client_frame(kFin | opcode, payload), 1 << 20, chunk);
        ASSERT_EQ(parsed.error, 0) << length;
        ASSERT_EQ(parsed.messages.size(), 1U) << length;
        EXPECT_EQ(static_cast<unsigned>(parsed.messages[0].opcode), opcode);
        EXPECT_EQ(parsed.messages[0].payload, payload) << length;
      }
    }
  }
}

TEST(WsConformance, FramesFedOneByteAtATimeGiveTheSameMessages) {
  const std::string bytes = client_frame(kText, "frag") + client_frame(kFin | kPing, "p") +
                            client_frame(kFin | kContinuation, "mented") +
                            client_frame(kFin | kBinary, std::string(300, 'b'));
  const Parsed parsed = parse(bytes, 1 << 20, 1);
  ASSERT_EQ(parsed.error, 0);
  ASSERT_EQ(parsed.messages.size(), 3U);
  EXPECT_EQ(parsed.messages[0].opcode, WsOpcode::kPing);
  EXPECT_EQ(parsed.messages[1].payload, "fragmented");
  EXPECT_EQ(parsed.messages[2].payload, std::string(300, 'b'));
}

TEST(WsConformance, AnUnmaskedClientFrameFails1002) {
  std::string frame = client_frame(kFin | kText, "hi");
  frame[1] = static_cast<char>(frame[1] & 0x7F);
  frame.erase(2, 4);
  EXPECT_EQ(parse(frame).error, kProtocolError);
}

TEST(WsConformance, A64BitLengthWithItsTopBitSetFails1002) {
  std::string frame{static_cast<char>(kFin | kBinary), static_cast<char>(0x80 | 127)};
  frame += std::string("\x80\x00\x00\x00\x00\x00\x00\x01", 8) + "mask";
  EXPECT_EQ(parse(frame).error, kProtocolError) << "not 1009: the length itself is invalid";
}

TEST(WsConformance, ALengthNotInItsShortestFormFails1002) {
  // RFC 6455 5.2: "the minimal number of bytes MUST be used to encode the length".
  std::string sixteen_bit{static_cast<char>(kFin | kText), static_cast<char>(0x80 | 126), 0, 5};
  EXPECT_EQ(parse(sixteen_bit + "mask" + "hello").error, kProtocolError);
  std::string sixty_four_bit{static_cast<char>(kFin | kText), static_cast<char>(0x80 | 127)};
  sixty_four_bit += std::string("\x00\x00\x00\x00\x00\x00\x01\x00", 8);
  EXPECT_EQ(parse(sixty_four_bit + "mask" + std::string(256, ' ')).error, kProtocolError);
}

// ---- 2.x: pings and pongs --------------------------------------------------------------------

TEST(WsConformance, Case2_1To2_4_PingsUpTo125BytesArePassedOnWithTheirPayload) {
  for (const std::string& payload :
       {std::string(), std::string("Hello, world!"), std::string("\x00\xff\xfe\xfd\xfc\xfb", 6),
        std::string(125, '\xfe')}) {
    const Parsed parsed = parse(client_frame(kFin | kPing, payload));
    ASSERT_EQ(parsed.error, 0);
    ASSERT_EQ(parsed.messages.size(), 1U);
    EXPECT_EQ(parsed.messages[0].opcode, WsOpcode::kPing);
    EXPECT_EQ(parsed.messages[0].payload, payload);
  }
}

TEST(WsConformance, Case2_5_APingOver125BytesFails1002) {
  EXPECT_EQ(parse(client_frame(kFin | kPing, std::string(126, 'p'))).error, kProtocolError);
  // Refused from the first two bytes, before the rest of the frame is there.
  EXPECT_EQ(parse(client_frame(kFin | kPing, std::string(126, 'p')).substr(0, 2)).error,
            kProtocolError);
}

TEST(WsConformance, Case2_7_AnUnsolicitedPongIsPassedOnForTheSessionToIgnore) {
  const Parsed parsed = parse(client_frame(kFin | kPong, "unsolicited"));
  ASSERT_EQ(parsed.error, 0);
  ASSERT_EQ(parsed.messages.size(), 1U);
  EXPECT_EQ(parsed.messages[0].opcode, WsOpcode::kPong);
}

// ---- 3.x: reserved bits ----------------------------------------------------------------------

TEST(WsConformance, Case3_ReservedBitsFail1002OnAnyFrame) {
  for (const unsigned rsv : {0x40U, 0x20U, 0x10U, 0x70U}) {
    for (const unsigned opcode : {kText, kBinary, kPing, kClose}) {
      EXPECT_EQ(parse(client_frame(kFin | rsv | opcode, "")).error, kProtocolError)
          << rsv << " " << opcode;
    }
  }
}

TEST(WsConformance, Case3_3_TheMessagesBeforeAFrameWithReservedBitsStillCount) {
  const Parsed parsed =
      parse(client_frame(kFin | kText, "ok") + client_frame(kFin | 0x20 | kText, "bad") +
            client_frame(kFin | kText, "never"));
  ASSERT_EQ(parsed.messages.size(), 1U);
  EXPECT_EQ(parsed.messages[0].payload, "ok");
  EXPECT_EQ(parsed.error, kProtocolError);
}

// ---- 4.x: reserved opcodes -------------------------------------------------------------------

TEST(WsConformance, Case4_ReservedOpcodesFail1002) {
  for (const unsigned opcode : {0x3U, 0x4U, 0x5U, 0x6U, 0x7U, 0xBU, 0xCU, 0xDU, 0xEU, 0xFU}) {
    EXPECT_EQ(parse(client_frame(kFin | opcode, "")).error, kProtocolError) << opcode;
    const Parsed after_a_message =
        parse(client_frame(kFin | kText, "ok") + client_frame(kFin | opcode, "payload"));
    EXPECT_EQ(after_a_message.messages.size(), 1U);
    EXPECT_EQ(after_a_message.error, kProtocolError) << opcode;
  }
}

// ---- 5.x: fragmentation ----------------------------------------------------------------------

TEST(WsConformance, Case5_1And5_2_FragmentedControlFramesFail1002) {
  for (const unsigned opcode : {kPing, kPong, kClose}) {
    EXPECT_EQ(
        parse(client_frame(opcode, "frag") + client_frame(kFin | kContinuation, "ment")).error,
        kProtocolError)
        << opcode;
  }
}

TEST(WsConformance, Case5_3To5_5_AMessageInFragmentsArrivesWhole) {
  for (const unsigned opcode : {kText, kBinary}) {
    const Parsed parsed = parse(client_frame(opcode, "frag") + client_frame(kContinuation, "") +
                                client_frame(kFin | kContinuation, "ment"));
    ASSERT_EQ(parsed.error, 0);
    ASSERT_EQ(parsed.messages.size(), 1U);
    EXPECT_EQ(static_cast<unsigned>(parsed.messages[0].opcode), opcode);
    EXPECT_EQ(parsed.messages[0].payload, "fragment");
  }
}

TEST(WsConformance, Case5_6To5_8_ControlFramesBetweenFragmentsComeFirst) {
  const Parsed parsed =
      parse(client_frame(kText, "frag") + client_frame(kFin | kPing, "ping") +
            client_frame(kFin | kPong, "pong") + client_frame(kFin | kContinuation, "ment"));
  ASSERT_EQ(parsed.error, 0);
  ASSERT_EQ(parsed.messages.size(), 3U);
  EXPECT_EQ(parsed.messages[0].opcode, WsOpcode::kPing);
  EXPECT_EQ(parsed.messages[0].payload, "ping");
  EXPECT_EQ(parsed.messages[1].opcode, WsOpcode::kPong);
  EXPECT_EQ(parsed.messages[2].payload, "fragment");
}

TEST(WsConformance, Case5_9To5_14_AContinuationWithNothingToContinueFails1002) {
  EXPECT_EQ(parse(client_frame(kFin | kContinuation, "x")).error, kProtocolError);
  EXPECT_EQ(parse(client_frame(kContinuation, "x")).error, kProtocolError);
  // Also once a message is complete (5.15): the next continuation has nothing to continue.
  const Parsed parsed = parse(client_frame(kText, "a") + client_frame(kFin | kContinuation, "b") +
                              client_frame(kContinuation, "c"));
  ASSERT_EQ(parsed.messages.size(), 1U);
  EXPECT_EQ(parsed.messages[0].payload, "ab");
  EXPECT_EQ(parsed.error, kProtocolError);
}

TEST(WsConformance, Case5_18_ANewDataFrameInsideAFragmentedMessageFails1002) {
  EXPECT_EQ(parse(client_frame(kText, "frag") + client_frame(kFin | kText, "new")).error,
            kProtocolError);
  EXPECT_EQ(parse(client_frame(kBinary, "frag") + client_frame(kBinary, "new")).error,
            kProtocolError);
}

TEST(WsConformance, Case5_19And5_20_ManyFragmentsWithPingsBetweenThem) {
  std::string bytes = client_frame(kText, "f1");
  for (int i = 2; i <= 5; ++i) {
    bytes += client_frame(kContinuation, "f" + std::to_string(i));
    bytes += client_frame(kFin | kPing, "p" + std::to_string(i));
  }
  bytes += client_frame(kFin | kContinuation, "end");
  for (const std::size_t chunk : {0UL, 1UL, 7UL}) {
    const Parsed parsed = parse(bytes, 1 << 20, chunk);
    ASSERT_EQ(parsed.error, 0);
    ASSERT_EQ(parsed.messages.size(), 5U);
    EXPECT_EQ(parsed.messages[3].payload, "p5");
    EXPECT_EQ(parsed.messages[4].payload, "f1f2f3f4f5end");
  }
}

// ---- 6.x: UTF-8 in text messages -------------------------------------------------------------

TEST(WsConformance, Case6_1_EmptyTextMessagesAreValid) {
  const Parsed parsed =
      parse(client_frame(kFin | kText, "") + client_frame(kText, "") +
            client_frame(kContinuation, "") + client_frame(kFin | kContinuation, ""));
  ASSERT_EQ(parsed.error, 0);
  EXPECT_EQ(parsed.messages.size(), 2U);
}

TEST(WsConformance, Case6_2_ValidUtf8SplitIntoFragmentsAnywhereIsValid) {
  const std::string text =
      "Hello-\xC2\xB5@\xC3\x9F\xC3\xB6\xC3\xA4\xC3\xBC\xC3\xA0\xC3\xA1-UTF-8!!"
      "\xF0\xA4\xAD\xA2\xE2\x82\xAC";
  for (std::size_t split = 0; split <= text.size(); ++split) {
    const Parsed parsed = parse(client_frame(kText, text.substr(0, split)) +
                                client_frame(kFin | kContinuation, text.substr(split)));
    ASSERT_EQ(parsed.error, 0) << split;
    ASSERT_EQ(parsed.messages.size(), 1U);
    EXPECT_EQ(parsed.messages[0].payload, text);
  }
  // One fragment per byte (6.2.4).
  std::string bytes;
  for (std::size_t i = 0; i < text.size(); ++i) {
    bytes += client_frame((i == 0 ? kText : kContinuation) | (i + 1 == text.size() ? kFin : 0U),
                          text.substr(i, 1));
  }
  const Parsed byte_by_byte = parse(bytes);
  ASSERT_EQ(byte_by_byte.error, 0);
  EXPECT_EQ(byte_by_byte.messages.at(0).payload, text);
}

TEST(WsConformance, Case6_3_InvalidUtf8Fails1007InOneFragmentOrMany) {
  const std::string text =
      std::string("\xCE\xBA\xE1\xBD\xB9\xCF\x83\xCE\xBC\xCE\xB5") + "\xED\xA0\x80" + "edited";
  EXPECT_EQ(parse(client_frame(kFin | kText, text)).error, kInvalidPayload);
  std::string bytes;
  for (std::size_t i = 0; i < text.size(); ++i) {
    bytes += client_frame((i == 0 ? kText : kContinuation) | (i + 1 == text.size() ? kFin : 0U),
                          text.substr(i, 1));
  }
  EXPECT_EQ(parse(bytes).error, kInvalidPayload);
}

TEST(WsConformance, Case6_4_InvalidUtf8FailsAtItsFragmentBeforeTheMessageEnds) {
  // The final fragment never comes: the bad one fails the connection by itself.
  WsFrameParser parser(1024);
  parser.feed(client_frame(kText, "\xCE\xBA\xE1\xBD\xB9\xCF\x83\xCE\xBC\xCE\xB5"));
  EXPECT_FALSE(parser.next().has_value());
  EXPECT_FALSE(parser.failed());
  parser.feed(client_frame(kContinuation, "\xF4\x90\x80\x80"));
  EXPECT_FALSE(parser.next().has_value());
  EXPECT_EQ(parser.error_code(), kInvalidPayload);
}

TEST(WsConformance, Case6_KuhnsInvalidSequencesFail1007) {
  for (const std::string& bad :
       {std::string("\xF8\x88\x80\x80\x80"), std::string("\xF4\x90\x80\x80"),
        std::string("\x80\xBF"), std::string("\xC0 "), std::string("\xFE\xFF"),
        std::string("\xC0\xAF"), std::string("\xE0\x80\xAF"), std::string("\xF0\x80\x80\xAF"),
        std::string("\xC0\x80"), std::string("\xED\xA0\x80"), std::string("\xED\xBF\xBF"),
        std::string("\xED\xA0\x80\xED\xB0\x80")}) {
    EXPECT_EQ(parse(client_frame(kFin | kText, "a" + bad + "z")).error, kInvalidPayload)
        << ::testing::PrintToString(bad);
  }
}

TEST(WsConformance, ATextMessageEndingInsideACodePointFails1007) {
  EXPECT_EQ(parse(client_frame(kFin | kText, "caf\xC3")).error, kInvalidPayload);
  EXPECT_EQ(
      parse(client_frame(kText, "caf") + client_frame(kFin | kContinuation, "\xE2\x82")).error,
      kInvalidPayload);
}

TEST(WsConformance, BinaryMessagesAreNotCheckedForUtf8) {
  const std::string bytes("\xFF\xFE\xED\xA0\x80\xC0", 6);
  const Parsed parsed = parse(client_frame(kFin | kBinary, bytes));
  ASSERT_EQ(parsed.error, 0);
  EXPECT_EQ(parsed.messages.at(0).payload, bytes);
}

// ---- 7.x: the close frame --------------------------------------------------------------------

TEST(WsConformance, Case7_1_NothingAfterACloseFrameIsParsed) {
  WsFrameParser parser(1024);
  parser.feed(client_frame(kFin | kText, "before") + client_frame(kFin | kClose, "") +
              client_frame(kFin | kText, "after") + client_frame(kFin | kPing, "after"));
  EXPECT_EQ(parser.next()->payload, "before");
  EXPECT_EQ(parser.next()->opcode, WsOpcode::kClose);
  EXPECT_TRUE(parser.closed());
  EXPECT_FALSE(parser.next().has_value());
  parser.feed(client_frame(kFin | kText, "later"));
  EXPECT_FALSE(parser.next().has_value());
  EXPECT_FALSE(parser.failed()) << "what follows a close is ignored, not a violation";
}

TEST(WsConformance, Case7_1_6_ACloseBetweenFragmentsEndsTheConnection) {
  const Parsed parsed = parse(client_frame(kText, "frag") + client_frame(kFin | kClose, "") +
                              client_frame(kFin | kContinuation, "ment"));
  ASSERT_EQ(parsed.error, 0);
  ASSERT_EQ(parsed.messages.size(), 1U);
  EXPECT_EQ(parsed.messages[0].opcode, WsOpcode::kClose);
}

TEST(WsConformance, Case7_3_ClosePayloadsThatAreValid) {
  for (const std::string& payload :
       {std::string(), close_payload(1000), close_payload(1000, "Hello World!"),
        close_payload(1000, std::string(123, '*')), close_payload(1001, "\xE2\x82\xAC")}) {
    const Parsed parsed = parse(client_frame(kFin | kClose, payload));
    EXPECT_EQ(parsed.error, 0) << ::testing::PrintToString(payload);
    ASSERT_EQ(parsed.messages.size(), 1U);
    EXPECT_EQ(parsed.messages[0].payload, payload);
  }
}

TEST(WsConformance, Case7_3_2_ACloseWithAOneBytePayloadFails1002) {
  EXPECT_EQ(parse(client_frame(kFin | kClose, "\x03")).error, kProtocolError);
}

TEST(WsConformance, Case7_3_6_ACloseOver125BytesFails1002) {
  EXPECT_EQ(parse(client_frame(kFin | kClose, close_payload(1000, std::string(124, '*')))).error,
            kProtocolError);
}

TEST(WsConformance, Case7_5_1_ACloseReasonThatIsNotUtf8Fails1007) {
  EXPECT_EQ(
      parse(client_frame(kFin | kClose, close_payload(1000,
                                                      "\xCE\xBA\xE1\xBD\xB9\xCF\x83\xCE\xBC\xCE\xB5"
                                                      "\xED\xA0\x80"
                                                      "edited")))
          .error,
      kInvalidPayload);
}

TEST(WsConformance, Case7_7_ValidCloseCodesAreAccepted) {
  for (const unsigned code : {1000U, 1001U, 1002U, 1003U, 1007U, 1008U, 1009U, 1010U, 1011U, 1012U,
                              1013U, 1014U, 3000U, 3999U, 4000U, 4999U}) {
    EXPECT_TRUE(is_valid_close_code(static_cast<std::uint16_t>(code))) << code;
    EXPECT_EQ(parse(client_frame(kFin | kClose, close_payload(code))).error, 0) << code;
  }
}

TEST(WsConformance, Case7_9And7_13_InvalidCloseCodesFail1002) {
  for (const unsigned code :
       {0U, 999U, 1004U, 1005U, 1006U, 1015U, 1016U, 1100U, 2000U, 2999U, 5000U, 65535U}) {
    EXPECT_FALSE(is_valid_close_code(static_cast<std::uint16_t>(code))) << code;
    EXPECT_EQ(parse(client_frame(kFin | kClose, close_payload(code))).error, kProtocolError)
        << code;
  }
}

TEST(WsConformance, TheServersCloseReasonIsCutAtACodePointBoundary) {
  const std::string reason = repeat("\xE2\x82\xAC", 60);  // 180 bytes of euro signs
  const std::string frame = encode_ws_close(1011, reason);
  ASSERT_LE(frame.size(), 2U + 125U);
  EXPECT_EQ(static_cast<unsigned char>(frame[1]), 2U + 123U - 123U % 3U);
  EXPECT_TRUE(is_valid_utf8(frame.substr(4)));
}

TEST(WsConformance, TheReplyToACloseEchoesItsCodeOnly) {
  EXPECT_EQ(encode_ws_close_reply(close_payload(4001, "bye")),
            encode_ws_frame(WsOpcode::kClose, close_payload(4001)));
  EXPECT_EQ(encode_ws_close_reply(""), encode_ws_frame(WsOpcode::kClose, ""));
}

// ---- 9.x / 10.4: the message size limit ------------------------------------------------------

TEST(WsConformance, AMessageAtTheLimitIsAcceptedAndOneByteMoreFails1009) {
  EXPECT_EQ(parse(client_frame(kFin | kText, std::string(1000, 'a')), 1000).error, 0);
  EXPECT_EQ(parse(client_frame(kFin | kText, std::string(1001, 'a')), 1000).error, kMessageTooBig);
  // From the header alone, without waiting for a payload that would not fit.
  EXPECT_EQ(parse(client_frame(kFin | kBinary, std::string(70000, 'a')).substr(0, 10), 1000).error,
            kMessageTooBig);
}

TEST(WsConformance, FragmentsThatTogetherExceedTheLimitFail1009) {
  EXPECT_EQ(parse(client_frame(kText, std::string(600, 'a')) +
                      client_frame(kFin | kContinuation, std::string(401, 'a')),
                  1000)
                .error,
            kMessageTooBig);
}

TEST(WsConformance, APingInsideANearlyFullMessageDoesNotCountTowardsIt) {
  const Parsed parsed = parse(client_frame(kText, std::string(990, 'a')) +
                                  client_frame(kFin | kPing, std::string(100, 'p')) +
                                  client_frame(kFin | kContinuation, std::string(10, 'a')),
                              1000);
  ASSERT_EQ(parsed.error, 0);
  ASSERT_EQ(parsed.messages.size(), 2U);
  EXPECT_EQ(parsed.messages[1].payload.size(), 1000U);
}

TEST(WsConformance, AFailedParserStaysFailed) {
  WsFrameParser parser(1024);
  parser.feed(client_frame(kFin | 0x40 | kText, "bad"));
  EXPECT_FALSE(parser.next().has_value());
  EXPECT_EQ(parser.error_code(), kProtocolError);
  parser.feed(client_frame(kFin | kText, "good"));
  EXPECT_FALSE(parser.next().has_value());
  EXPECT_EQ(parser.error_code(), kProtocolError);
}

// ---- through a StreamSession: the close handshake and the codes the server sends -------------

class WsSessionConformance : public test::StreamSessionTest {
 protected:
  // The server's close frame, read after anything it sent before it; the connection must end
  // right after it.
  static std::optional<Frame> close_reply(test::Client& client) {
    std::optional<Frame> close;
    while (auto frame = client.read()) {
      EXPECT_FALSE(close.has_value()) << "a frame after the close frame";
      if (frame->opcode == kClose) close = std::move(frame);
    }
    return close;
  }

  void expect_closed_with(std::string_view bytes, unsigned code) {
    auto client = open();
    client->send_raw(bytes);
    const auto close = close_reply(*client);
    ASSERT_TRUE(close.has_value()) << "no close frame; expected " << code;
    EXPECT_EQ(close->close_code(), code);
    EXPECT_TRUE(client->connection_ended());
  }
};

TEST_F(WsSessionConformance, Case7_7_AClientCloseIsEchoedWithItsCodeAndTheTcpConnectionCloses) {
  for (const unsigned code : {1000U, 1001U, 1003U, 3000U, 4999U}) {
    auto client = open();
    client->send_raw(client_frame(kFin | kClose, close_payload(code, "bye")));
    const auto close = close_reply(*client);
    ASSERT_TRUE(close.has_value()) << code;
    EXPECT_EQ(close->payload, close_payload(code)) << "the code echoed, without the reason";
    EXPECT_TRUE(client->connection_ended()) << "the server closes the TCP connection (7.1.1)";
  }
  EXPECT_TRUE(wait_for_clients(0));
}

TEST_F(WsSessionConformance, Case7_3_1_AnEmptyClientCloseIsAnsweredWithAnEmptyClose) {
  auto client = open();
  client->send_raw(client_frame(kFin | kClose, ""));
  const auto close = close_reply(*client);
  ASSERT_TRUE(close.has_value());
  EXPECT_TRUE(close->payload.empty());
  EXPECT_TRUE(client->connection_ended());
}

TEST_F(WsSessionConformance, Case7_1_NothingTheClientSendsAfterItsCloseIsCarriedOut) {
  auto client = open(Role::kOperator);
  robot_.answers.defer = true;  // a teleop would stay pending: visible below
  client->send_raw(client_frame(kFin | kClose, close_payload(1000)) +
                   client_frame(kFin | kText, R"({"op":"ping","id":1})") +
                   client_frame(kFin | kText, R"({"op":"teleop","v":0.5,"w":0})") +
                   client_frame(kFin | kPing, "late"));
  const std::vector<Frame> frames = client->read_to_end();
  ASSERT_EQ(frames.size(), 1U) << "only the close reply: no pong, no op reply";
  EXPECT_EQ(frames[0].opcode, kClose);
  EXPECT_EQ(robot_.answers.pending(), 0U);
}

TEST_F(WsSessionConformance, Case7_9_InvalidCloseCodesAreAnswered1002) {
  for (const unsigned code : {0U, 999U, 1004U, 1005U, 1006U, 1015U, 1016U, 2999U, 5000U}) {
    expect_closed_with(client_frame(kFin | kClose, close_payload(code)), kProtocolError);
  }
  expect_closed_with(client_frame(kFin | kClose, "\x03"), kProtocolError);
}

TEST_F(WsSessionConformance, Case7_5_1_ACloseReasonThatIsNotUtf8IsAnswered1007) {
  expect_closed_with(client_frame(kFin | kClose, close_payload(1000, "\xED\xA0\x80")),
                     kInvalidPayload);
}

TEST_F(WsSessionConformance, Case6_InvalidUtf8TextIsAnswered1007) {
  expect_closed_with(client_frame(kFin | kText, "{\"op\":\"ping\",\"id\":\"\xC0\xAF\"}"),
                     kInvalidPayload);
  expect_closed_with(client_frame(kText, "{\"op\":\"ping\",\"id\":\"\xED") +
                         client_frame(kFin | kContinuation, "\xA0\x80\"}"),
                     kInvalidPayload);
}

TEST_F(WsSessionConformance, Case6_2_ATextMessageSplitInsideACodePointIsHandled) {
  auto client = open();
  // "é" is C3 A9: the first fragment ends after C3.
  client->send_raw(client_frame(kText, "{\"op\":\"ping\",\"id\":\"caf\xC3") +
                   client_frame(kFin | kContinuation, "\xA9\"}"));
  EXPECT_TRUE(client->read_until("\"id\":\"caf\xC3\xA9\""));
}

TEST_F(WsSessionConformance, Case2_2_APingIsAnsweredWithAPongCarryingItsPayload) {
  auto client = open();
  const std::string payload("\x00\xff\xfe\xfd\xfc\xfb\x00\xff", 8);
  client->send_raw(client_frame(kFin | kPing, payload));
  std::optional<Frame> pong;
  while ((pong = client->read()) && pong->opcode != kPong) {
  }
  ASSERT_TRUE(pong.has_value());
  EXPECT_EQ(pong->payload, payload);
  EXPECT_TRUE(pong->fin);
}

TEST_F(WsSessionConformance, Case2_7_AnUnsolicitedPongIsIgnored) {
  auto client = open();
  client->send_raw(client_frame(kFin | kPong, "unsolicited") +
                   client_frame(kFin | kText, R"({"op":"ping","id":7})"));
  const auto reply = client->read();
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->opcode, kText) << "nothing answers the pong";
  EXPECT_NE(reply->payload.find(R"("id":7)"), std::string::npos) << reply->payload;
}

TEST_F(WsSessionConformance, Case4_AReservedOpcodeIsAnswered1002) {
  expect_closed_with(client_frame(kFin | 0xB, "x"), kProtocolError);
}

TEST_F(WsSessionConformance, Case5_AContinuationWithNothingToContinueIsAnswered1002) {
  expect_closed_with(client_frame(kFin | kContinuation, "x"), kProtocolError);
}

TEST_F(WsSessionConformance, Case9_AMessageOverTheLimitIsAnswered1009) {
  // The default limit is 64 KiB; the header alone is enough.
  expect_closed_with(client_frame(kFin | kText, std::string(70 * 1024, ' ')).substr(0, 14),
                     kMessageTooBig);
}

TEST_F(WsSessionConformance, AViolationThatCameWithTheUpgradeRequestIsAnswered1002) {
  // Frames pipelined behind the HTTP upgrade reach the session with it, not through a read.
  std::string unmasked = client_frame(kFin | kText, "{}");
  unmasked[1] = static_cast<char>(unmasked[1] & 0x7F);
  auto client = open(Role::kViewer, 0, unmasked.substr(0, 2) + unmasked.substr(6));
  const auto close = close_reply(*client);
  ASSERT_TRUE(close.has_value()) << "the session waited for more bytes instead";
  EXPECT_EQ(close->close_code(), kProtocolError);
  EXPECT_TRUE(client->connection_ended());
}

}  // namespace
}  // namespace mobot::api
