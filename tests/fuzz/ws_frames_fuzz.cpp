// libFuzzer target: a WebSocket client's bytes as a stream session reads them
// (api/websocket_frames: WsFrameParser), in read sizes that vary as TCP delivers them. Beyond not
// crashing: the same bytes split differently give the same messages and the same error, a failed
// parser stays failed, no message is over the limit, every text message and close reason is UTF-8,
// control frames are short, and nothing comes after a close frame.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "api/utf8_validator.h"
#include "api/websocket_frames.h"

namespace {

using mobot::api::WsFrameParser;
using mobot::api::WsMessage;
using mobot::api::WsOpcode;

struct Outcome {
  std::vector<WsMessage> messages;
  std::uint16_t error = 0;
};

void check(bool condition) {
  if (!condition) __builtin_trap();
}

void check_message(const WsMessage& message, std::size_t limit) {
  check(message.payload.size() <= limit);
  switch (message.opcode) {
    case WsOpcode::kText:
      check(mobot::api::is_valid_utf8(message.payload));
      break;
    case WsOpcode::kClose:
      check(message.payload.size() <= 125 && message.payload.size() != 1);
      if (message.payload.size() >= 2) {
        const auto code =
            static_cast<std::uint16_t>((static_cast<unsigned char>(message.payload[0]) << 8) |
                                       static_cast<unsigned char>(message.payload[1]));
        check(mobot::api::is_valid_close_code(code));
        check(mobot::api::is_valid_utf8(std::string_view(message.payload).substr(2)));
      }
      break;
    case WsOpcode::kPing:
    case WsOpcode::kPong:
      check(message.payload.size() <= 125);
      break;
    case WsOpcode::kBinary:
      break;
    case WsOpcode::kContinuation:
      check(false);  // fragments are joined, never handed out
  }
}

// Feeds `bytes` in reads whose sizes come from `seed`, taking the messages after each read as the
// session does.
Outcome parse(std::string_view bytes, std::size_t limit, std::uint32_t seed) {
  WsFrameParser parser(limit);
  Outcome outcome;
  std::uint32_t state = seed | 1U;
  std::size_t at = 0;
  while (at < bytes.size()) {
    state = state * 1664525U + 1013904223U;
    const std::size_t read_bytes = seed == 0 ? bytes.size() : 1 + (state >> 24) % 97;
    parser.feed(bytes.substr(at, read_bytes));
    at += read_bytes;
    const bool was_closed = parser.closed();
    while (auto message = parser.next()) {
      check(!was_closed);
      check_message(*message, limit);
      outcome.messages.push_back(std::move(*message));
      if (outcome.messages.back().opcode == WsOpcode::kClose) check(parser.closed());
    }
    if (parser.failed()) {
      // Failed for good: more bytes change nothing.
      const std::uint16_t error = parser.error_code();
      check(error == 1002 || error == 1007 || error == 1009);
      parser.feed(bytes);
      check(!parser.next().has_value());
      check(parser.error_code() == error);
      outcome.error = error;
      break;
    }
  }
  return outcome;
}

bool same(const Outcome& a, const Outcome& b) {
  if (a.error != b.error || a.messages.size() != b.messages.size()) return false;
  for (std::size_t i = 0; i < a.messages.size(); ++i) {
    if (a.messages[i].opcode != b.messages[i].opcode ||
        a.messages[i].payload != b.messages[i].payload) {
      return false;
    }
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  // The first byte picks the message limit: the server's 64 KiB, or a small one so that the
  // 1009 paths are reached with short inputs; the second the read sizes.
  const std::size_t limit = data[0] == 0xFF ? 64 * 1024 : 1 + std::size_t{data[0]} * 4;
  const std::string_view bytes(reinterpret_cast<const char*>(data) + 2, size - 2);
  const Outcome whole = parse(bytes, limit, 0);
  const Outcome pieces = parse(bytes, limit, data[1] + 1U);
  check(same(whole, pieces));
  return 0;
}
