#include "api/websocket_frames.h"

#include <openssl/evp.h>
#include <openssl/sha.h>

#include <array>

namespace mobot::api {
namespace {

constexpr std::uint16_t kProtocolError = 1002;
constexpr std::uint16_t kMessageTooBig = 1009;

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
  payload.append(reason.substr(0, 120));
  return encode_ws_frame(WsOpcode::kClose, payload);
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

std::optional<WsMessage> WsFrameParser::fail(std::uint16_t code, std::string message) {
  error_code_ = code;
  error_message_ = std::move(message);
  buffer_.clear();
  consumed_ = 0;
  return std::nullopt;
}

std::optional<WsMessage> WsFrameParser::next() {
  while (!failed()) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(buffer_.data()) + consumed_;
    const std::size_t available = buffer_.size() - consumed_;
    if (available < 2) break;
    const bool fin = (bytes[0] & 0x80U) != 0;
    if ((bytes[0] & 0x70U) != 0) return fail(kProtocolError, "reserved bits set");
    const unsigned raw_opcode = bytes[0] & 0x0FU;
    if (!is_known(raw_opcode)) return fail(kProtocolError, "unknown opcode");
    const auto opcode = static_cast<WsOpcode>(raw_opcode);
    if ((bytes[1] & 0x80U) == 0) return fail(kProtocolError, "client frames must be masked");

    std::size_t header_bytes = 2;
    std::uint64_t length = bytes[1] & 0x7FU;
    if (length == 126) {
      header_bytes = 4;
      if (available < header_bytes) break;
      length = (std::uint64_t{bytes[2]} << 8) | bytes[3];
    } else if (length == 127) {
      header_bytes = 10;
      if (available < header_bytes) break;
      length = 0;
      for (int i = 2; i < 10; ++i) length = (length << 8) | bytes[i];
    }
    if (is_control(opcode) && (!fin || length > 125)) {
      return fail(kProtocolError, "control frames must be short and unfragmented");
    }
    const std::size_t partial_bytes = partial_ ? partial_->payload.size() : 0;
    if (length > max_message_bytes_ || partial_bytes + length > max_message_bytes_) {
      return fail(kMessageTooBig, "message too big");
    }
    header_bytes += 4;  // the masking key
    if (available < header_bytes + length) break;

    const unsigned char* mask = bytes + header_bytes - 4;
    std::string payload(reinterpret_cast<const char*>(bytes + header_bytes),
                        static_cast<std::size_t>(length));
    for (std::size_t i = 0; i < payload.size(); ++i) {
      payload[i] = static_cast<char>(static_cast<unsigned char>(payload[i]) ^ mask[i % 4]);
    }
    consumed_ += header_bytes + static_cast<std::size_t>(length);
    if (consumed_ > 65536 || consumed_ == buffer_.size()) {
      buffer_.erase(0, consumed_);
      consumed_ = 0;
    }

    if (is_control(opcode)) return WsMessage{opcode, std::move(payload)};
    if (opcode == WsOpcode::kContinuation) {
      if (!partial_) return fail(kProtocolError, "continuation without a message");
      partial_->payload.append(payload);
    } else {
      if (partial_) return fail(kProtocolError, "new message inside a fragmented one");
      partial_ = WsMessage{opcode, std::move(payload)};
    }
    if (fin) {
      WsMessage message = std::move(*partial_);
      partial_.reset();
      return message;
    }
  }
  return std::nullopt;
}

}  // namespace mobot::api
