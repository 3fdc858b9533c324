#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace mobot::api {

// RFC 6455 framing, server side. We frame messages ourselves (Beast still parses the HTTP upgrade)
// because a server frame is the same bytes for every client: each frame is encoded once, shared by
// all sessions, and a session's backlog goes out as one gathered write.
enum class WsOpcode : std::uint8_t {
  kContinuation = 0x0,
  kText = 0x1,
  kBinary = 0x2,
  kClose = 0x8,
  kPing = 0x9,
  kPong = 0xA,
};

// A complete unmasked server frame (FIN set): header followed by the payload.
std::string encode_ws_frame(WsOpcode opcode, std::string_view payload);
// A close frame carrying a status code and a short reason.
std::string encode_ws_close(std::uint16_t code, std::string_view reason);

// The Sec-WebSocket-Accept value for a client's Sec-WebSocket-Key.
std::string websocket_accept_key(std::string_view client_key);

// One complete message from the client: data messages are reassembled from fragments.
struct WsMessage {
  WsOpcode opcode = WsOpcode::kText;
  std::string payload;
};

// Incremental parser of client frames. Clients must mask; messages larger than the limit, bad
// opcodes, reserved bits and fragmented control frames are protocol errors (the connection closes
// with the code in error_code()).
class WsFrameParser {
 public:
  explicit WsFrameParser(std::size_t max_message_bytes) : max_message_bytes_(max_message_bytes) {}

  // Appends received bytes.
  void feed(std::string_view bytes) { buffer_.append(bytes); }
  // The next complete message, nullopt when more bytes are needed or on error.
  std::optional<WsMessage> next();
  bool failed() const { return error_code_ != 0; }
  std::uint16_t error_code() const { return error_code_; }
  const std::string& error_message() const { return error_message_; }

 private:
  std::optional<WsMessage> fail(std::uint16_t code, std::string message);

  std::size_t max_message_bytes_;
  std::string buffer_;
  std::size_t consumed_ = 0;
  std::optional<WsMessage> partial_;  // a data message whose final fragment has not arrived
  std::uint16_t error_code_ = 0;
  std::string error_message_;
};

}  // namespace mobot::api
