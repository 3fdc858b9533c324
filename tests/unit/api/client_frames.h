// WebSocket frames as a client sends them (masked), for the tests of the frame parser and of the
// stream sessions.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace mobot::api::test {

// A masked client frame with any first byte (FIN, reserved bits, opcode), in the shortest length
// form.
inline std::string client_frame(unsigned first_byte, std::string_view payload,
                                std::array<unsigned char, 4> mask = {0x37, 0xfa, 0x21, 0x3d}) {
  std::string frame;
  frame.push_back(static_cast<char>(first_byte));
  if (payload.size() < 126) {
    frame.push_back(static_cast<char>(0x80U | payload.size()));
  } else if (payload.size() <= 0xFFFF) {
    frame.push_back(static_cast<char>(0x80U | 126U));
    frame.push_back(static_cast<char>(payload.size() >> 8));
    frame.push_back(static_cast<char>(payload.size() & 0xFF));
  } else {
    frame.push_back(static_cast<char>(0x80U | 127U));
    for (int shift = 56; shift >= 0; shift -= 8) {
      frame.push_back(
          static_cast<char>((static_cast<std::uint64_t>(payload.size()) >> shift) & 0xFF));
    }
  }
  for (auto m : mask) frame.push_back(static_cast<char>(m));
  for (std::size_t i = 0; i < payload.size(); ++i) {
    frame.push_back(static_cast<char>(static_cast<unsigned char>(payload[i]) ^ mask[i % 4]));
  }
  return frame;
}

// A close frame's payload: the status code, then the reason.
inline std::string close_payload(unsigned code, std::string_view reason = "") {
  std::string payload{static_cast<char>(code >> 8), static_cast<char>(code & 0xFF)};
  payload.append(reason);
  return payload;
}

}  // namespace mobot::api::test
