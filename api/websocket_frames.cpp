#include "api/websocket_frames.h"

#include <openssl/evp.h>
#include <openssl/sha.h>

#include <array>
#include <cstring>

namespace mobot::api {
namespace {

constexpr std::uint16_t kProtocolError = 1002;
constexpr std::uint16_t kInvalidPayload = 1007;
constexpr std::uint16_t kMessageTooBig = 1009;
constexpr std::size_t kMaxControlPayload = 125;  // RFC 6455 5.5
constexpr std::size_t kMaxCloseReason = kMaxControlPayload - 2;
constexpr std::size_t kMaskBytes = 4;
// Consumed bytes are dropped from the front of the buffer once this many have gathered (or all of
// it is consumed): one move per 64 KiB rather than one per frame.
constexpr std::size_t kCompactBytes = 65536;

std::string frame_header(WsOpcode opcode, std::size_t payload_bytes) {
  std::string header;
  header.push_back(static_cast<char>(0x80U | static_cast<unsigned>(opcode)));
  if (payload_bytes < 126) {
    header.push_back(static_cast<char>(payload_bytes));
  } else if (payload_bytes <= 0xFFFF) {
    header.push_back(static_cast<char>(126));
    header.push_back(static_cast<char>((payload_bytes >> 8) & 0xFF));
    header.push_back(static_cast<char>(payload_bytes & 0xFF));
  } else {
    header.push_back(static_cast<char>(127));
    for (int shift = 56; shift >= 0; shift -= 8) {
      header.push_back(
          static_cast<char>((static_cast<std::uint64_t>(payload_bytes) >> shift) & 0xFF));
    }
  }
  return header;
}

bool is_control(WsOpcode opcode) { return (static_cast<unsigned>(opcode) & 0x8U) != 0; }

bool is_known(unsigned opcode) { return opcode <= 0x2 || (opcode >= 0x8 && opcode <= 0xA); }

// XORs the payload with the client's masking key (RFC 6455 5.3), eight bytes at a time.
void unmask(char* payload, std::size_t size, const unsigned char* key) {
  unsigned char key8[8];
  for (std::size_t i = 0; i < sizeof key8; ++i) key8[i] = key[i % kMaskBytes];
  std::uint64_t key_word = 0;
  std::memcpy(&key_word, key8, sizeof key_word);
  std::size_t i = 0;
  for (; i + sizeof key_word <= size; i += sizeof key_word) {
    std::uint64_t word = 0;
    std::memcpy(&word, payload + i, sizeof word);
    word ^= key_word;
    std::memcpy(payload + i, &word, sizeof word);
  }
  for (; i < size; ++i) {
    payload[i] = static_cast<char>(static_cast<unsigned char>(payload[i]) ^ key[i % kMaskBytes]);
  }
}

// The longest prefix of `text` of at most `max_bytes` that does not end inside a code point.
std::string_view cut_at_code_point(std::string_view text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return text;
  std::size_t end = max_bytes;
  while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0U) == 0x80U) --end;
  return text.substr(0, end);
}

}  // namespace

std::string encode_ws_frame(WsOpcode opcode, std::string_view payload) {
  std::string frame = frame_header(opcode, payload.size());
  frame.append(payload);
  return frame;
}

std::string encode_ws_close(std::uint16_t code, std::string_view reason) {
  std::string payload;
  payload.push_back(static_cast<char>(code >> 8));
  payload.push_back(static_cast<char>(code & 0xFF));
  payload.append(cut_at_code_point(reason, kMaxCloseReason));
  return encode_ws_frame(WsOpcode::kClose, payload);
}

std::string encode_ws_close_reply(std::string_view client_close_payload) {
  return encode_ws_frame(WsOpcode::kClose, client_close_payload.substr(0, 2));
}

bool is_valid_close_code(std::uint16_t code) {
  return (code >= 1000 && code <= 1003) || (code >= 1007 && code <= 1014) ||
         (code >= 3000 && code <= 4999);
}

std::string websocket_accept_key(std::string_view client_key) {
  static constexpr std::string_view kGuid = "258EAFA5-E914-47DA-95CA-C5AB0DC85B11";
  std::string input(client_key);
  input.append(kGuid);
  std::array<unsigned char, SHA_DIGEST_LENGTH> digest{};
  SHA1(reinterpret_cast<const unsigned char*>(input.data()), input.size(), digest.data());
  std::array<unsigned char, 4 * ((SHA_DIGEST_LENGTH + 2) / 3) + 1> encoded{};
  const int length = EVP_EncodeBlock(encoded.data(), digest.data(), SHA_DIGEST_LENGTH);
  return {reinterpret_cast<const char*>(encoded.data()), static_cast<std::size_t>(length)};
}

std::nullopt_t WsFrameParser::fail(std::uint16_t code, std::string message) {
  error_code_ = code;
  error_message_ = std::move(message);
  buffer_.clear();
  consumed_ = 0;
  partial_.reset();
  return std::nullopt;
}

std::optional<WsMessage> WsFrameParser::next() {
  while (!failed() && !closed_) {
    const std::optional<FrameHeader> header = read_header();
    if (!header) break;
    const std::size_t frame_bytes = header->header_bytes + header->payload_bytes;
    if (buffer_.size() - consumed_ < frame_bytes) break;
    const auto* frame = reinterpret_cast<const unsigned char*>(buffer_.data()) + consumed_;
    std::optional<WsMessage> message =
        is_control(header->opcode) ? take_control(*header, frame) : take_data(*header, frame);
    if (failed()) break;
    drop_consumed(frame_bytes);
    if (message) return message;
  }
  return std::nullopt;
}

std::optional<WsFrameParser::FrameHeader> WsFrameParser::read_header() {
  const auto* bytes = reinterpret_cast<const unsigned char*>(buffer_.data()) + consumed_;
  const std::size_t available = buffer_.size() - consumed_;
  if (available < 2) return std::nullopt;
  FrameHeader header;
  header.fin = (bytes[0] & 0x80U) != 0;
  if ((bytes[0] & 0x70U) != 0) return fail(kProtocolError, "reserved bits set");
  const unsigned raw_opcode = bytes[0] & 0x0FU;
  if (!is_known(raw_opcode)) return fail(kProtocolError, "reserved opcode");
  header.opcode = static_cast<WsOpcode>(raw_opcode);
  if ((bytes[1] & 0x80U) == 0) {
    return fail(kProtocolError, "client frames must be masked");
  }
  if (!check_sequence(header.fin, header.opcode)) return std::nullopt;
  const unsigned short_length = bytes[1] & 0x7FU;
  // A control frame says so in its first two bytes (RFC 6455 5.5): fail before the rest arrives.
  if (is_control(header.opcode) && short_length > kMaxControlPayload) {
    return fail(kProtocolError, "control frames carry at most 125 bytes");
  }
  std::uint64_t length = short_length;
  header.header_bytes = 2;
  if (short_length == 126) {
    header.header_bytes = 4;
    if (available < header.header_bytes) return std::nullopt;
    length = (std::uint64_t{bytes[2]} << 8) | bytes[3];
    if (length < 126) return fail(kProtocolError, "length not minimally encoded");
  } else if (short_length == 127) {
    header.header_bytes = 10;
    if (available < header.header_bytes) return std::nullopt;
    length = 0;
    for (int i = 2; i < 10; ++i) length = (length << 8) | bytes[i];
    // RFC 6455 5.2: the most significant bit of a 64-bit length must be 0.
    if ((length >> 63) != 0) return fail(kProtocolError, "length top bit set");
    if (length <= 0xFFFF) return fail(kProtocolError, "length not minimally encoded");
  }
  // Control frames interleaved in a fragmented message do not count towards it.
  const std::size_t message_bytes =
      is_control(header.opcode) || !partial_ ? 0 : partial_->payload.size();
  if (length > max_message_bytes_ - message_bytes) {
    return fail(kMessageTooBig, "message too big");
  }
  header.payload_bytes = static_cast<std::size_t>(length);
  header.header_bytes += kMaskBytes;
  return header;
}

// RFC 6455 5.4, 5.5: control frames are whole; a continuation continues an open message and a
// new data frame waits until the open one is finished.
bool WsFrameParser::check_sequence(bool fin, WsOpcode opcode) {
  if (is_control(opcode)) {
    if (!fin) fail(kProtocolError, "fragmented control frame");
  } else if (opcode == WsOpcode::kContinuation) {
    if (!partial_) fail(kProtocolError, "continuation without a message");
  } else if (partial_) {
    fail(kProtocolError, "new message inside a fragmented one");
  }
  return !failed();
}

std::optional<WsMessage> WsFrameParser::take_control(const FrameHeader& header,
                                                     const unsigned char* frame) {
  WsMessage message{header.opcode,
                    std::string(reinterpret_cast<const char*>(frame) + header.header_bytes,
                                header.payload_bytes)};
  unmask(message.payload.data(), message.payload.size(), frame + header.header_bytes - kMaskBytes);
  if (header.opcode == WsOpcode::kClose) {
    if (!check_close(message.payload)) return std::nullopt;
    closed_ = true;
  }
  return message;
}

// RFC 6455 5.5.1, 7.4: no payload, or a status code a client may send and a UTF-8 reason.
bool WsFrameParser::check_close(std::string_view payload) {
  if (payload.empty()) return true;
  if (payload.size() == 1) {
    fail(kProtocolError, "close frame with a 1-byte payload");
    return false;
  }
  const auto code = static_cast<std::uint16_t>((static_cast<unsigned char>(payload[0]) << 8) |
                                               static_cast<unsigned char>(payload[1]));
  if (!is_valid_close_code(code)) {
    fail(kProtocolError, "invalid close code " + std::to_string(code));
    return false;
  }
  if (!is_valid_utf8(payload.substr(2))) {
    fail(kInvalidPayload, "close reason is not UTF-8");
    return false;
  }
  return true;
}

std::optional<WsMessage> WsFrameParser::take_data(const FrameHeader& header,
                                                  const unsigned char* frame) {
  if (header.opcode != WsOpcode::kContinuation) {
    partial_ = WsMessage{header.opcode, {}};
    partial_text_.reset();
  }
  std::string& payload = partial_->payload;
  const std::size_t offset = payload.size();
  payload.append(reinterpret_cast<const char*>(frame) + header.header_bytes, header.payload_bytes);
  unmask(payload.data() + offset, header.payload_bytes, frame + header.header_bytes - kMaskBytes);
  // RFC 6455 8.1: checked fragment by fragment, so a bad message fails before its end arrives.
  if (partial_->opcode == WsOpcode::kText &&
      !partial_text_.feed(std::string_view(payload).substr(offset))) {
    return fail(kInvalidPayload, "text message is not UTF-8");
  }
  if (!header.fin) return std::nullopt;
  if (partial_->opcode == WsOpcode::kText && !partial_text_.complete()) {
    return fail(kInvalidPayload, "text message ends inside a UTF-8 sequence");
  }
  WsMessage message = std::move(*partial_);
  partial_.reset();
  return message;
}

void WsFrameParser::drop_consumed(std::size_t frame_bytes) {
  consumed_ += frame_bytes;
  if (closed_) {
    buffer_.clear();  // what follows a close frame is not read (RFC 6455 5.5.1)
    consumed_ = 0;
  } else if (consumed_ > kCompactBytes || consumed_ == buffer_.size()) {
    buffer_.erase(0, consumed_);
    consumed_ = 0;
  }
}

}  // namespace mobot::api
