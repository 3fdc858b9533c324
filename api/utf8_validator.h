#pragma once

#include <cstdint>
#include <string_view>

namespace mobot::api {

// Checks that bytes are UTF-8 as RFC 3629 defines it, fed in pieces: a WebSocket text message
// arrives in fragments and a code point may straddle two of them (RFC 6455 5.6, 8.1). Overlong
// forms, UTF-16 surrogates (U+D800..U+DFFF) and code points above U+10FFFF are refused at the
// byte that makes them invalid, so a bad message fails at its first bad fragment.
class Utf8Validator {
 public:
  // False once the bytes fed so far cannot be the start of valid UTF-8; it stays false.
  bool feed(std::string_view bytes);
  // Everything fed is valid and ends on a code point boundary.
  bool complete() const { return !failed_ && pending_ == 0; }
  void reset() { *this = Utf8Validator{}; }

 private:
  bool fail() {
    failed_ = true;
    return false;
  }

  std::uint8_t pending_ = 0;  // continuation bytes the current code point still needs
  // The range its next continuation byte must fall in: narrower than 0x80..0xBF right after the
  // leading bytes that could otherwise start an overlong form, a surrogate or a code point beyond
  // U+10FFFF (E0, ED, F0, F4).
  std::uint8_t next_min_ = 0x80;
  std::uint8_t next_max_ = 0xBF;
  bool failed_ = false;
};

// The whole of `text` is valid UTF-8.
bool is_valid_utf8(std::string_view text);

}  // namespace mobot::api
