#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "api/utf8_validator.h"

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
// A close frame carrying a status code and a short reason (cut to the 123 bytes a control frame
// leaves for it, at a code point boundary: the reason must stay UTF-8).
std::string encode_ws_close(std::uint16_t code, std::string_view reason);
// The close frame that answers a client's close frame (RFC 6455 5.5.1): its status code echoed,
// or no code when it had none.
std::string encode_ws_close_reply(std::string_view client_close_payload);
// A status code an endpoint may send in a close frame (RFC 6455 7.4.1, 7.4.2 and the IANA
// registry): 1000-1003, 1007-1014, 3000-4999. 1005, 1006 and 1015 only report what happened
// locally and never go on the wire.
bool is_valid_close_code(std::uint16_t code);

// The Sec-WebSocket-Accept value for a client's Sec-WebSocket-Key.
std::string websocket_accept_key(std::string_view client_key);

// One complete message from the client: data messages are reassembled from fragments.
struct WsMessage {
  WsOpcode opcode = WsOpcode::kText;
  std::string payload;
};

// Incremental parser of client frames (RFC 6455 section 5). Any violation fails the connection
// with the code in error_code(), checked as soon as the bytes that break it arrive:
//  - 1002: an unmasked frame, reserved bits, a reserved opcode, a payload length that is not
//    minimally encoded or has its top bit set, a control frame over 125 bytes or fragmented, a
//    continuation with no message to continue, a data frame inside a fragmented message, a close
//    frame with a 1-byte payload or a status code a client may not send;
//  - 1007: a text message, or a close frame's reason, that is not UTF-8;
//  - 1009: a message over max_message_bytes (all its fragments together).
// Control frames between the fragments of a message are passed on as they come. A failed parser
// stays failed, and after a close frame it takes nothing more (RFC 6455 5.5.1).
class WsFrameParser {
 public:
  explicit WsFrameParser(std::size_t max_message_bytes) : max_message_bytes_(max_message_bytes) {}

  // Appends received bytes (dropped once the parser failed or passed on a close frame).
  void feed(std::string_view bytes) {
    if (!failed() && !closed_) buffer_.append(bytes);
  }
  // The next complete message, nullopt when more bytes are needed or on error.
  std::optional<WsMessage> next();
  bool failed() const { return error_code_ != 0; }
  std::uint16_t error_code() const { return error_code_; }
  const std::string& error_message() const { return error_message_; }
  // next() has returned a close frame: the client says nothing more.
  bool closed() const { return closed_; }

 private:
  struct FrameHeader {
    bool fin = false;
    WsOpcode opcode = WsOpcode::kContinuation;
    std::size_t header_bytes = 0;  // including the masking key
    std::size_t payload_bytes = 0;
  };

  // The header at the front of the buffer once it is complete and valid; nullopt while bytes are
  // missing or when it broke the protocol (then failed()).
  std::optional<FrameHeader> read_header();
  bool check_sequence(bool fin, WsOpcode opcode);
  std::optional<WsMessage> take_control(const FrameHeader& header, const unsigned char* frame);
  std::optional<WsMessage> take_data(const FrameHeader& header, const unsigned char* frame);
  bool check_close(std::string_view payload);
  void drop_consumed(std::size_t frame_bytes);
  // Records the error and drops everything buffered; nullopt for the caller to return.
  std::nullopt_t fail(std::uint16_t code, std::string message);

  std::size_t max_message_bytes_;
  std::string buffer_;
  std::size_t consumed_ = 0;
  std::optional<WsMessage> partial_;  // a data message whose final fragment has not arrived
  Utf8Validator partial_text_;        // the UTF-8 of partial_'s fragments so far, when text
  bool closed_ = false;
  std::uint16_t error_code_ = 0;
  std::string error_message_;
};

}  // namespace mobot::api
