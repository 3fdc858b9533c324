#include "api/utf8_validator.h"

#include <cstring>

namespace mobot::api {
namespace {

constexpr std::uint64_t kHighBits = 0x8080808080808080ULL;

// Client messages are JSON and almost always ASCII: eight bytes are checked at once until the
// first byte with its high bit set.
std::size_t skip_ascii(const unsigned char* bytes, std::size_t at, std::size_t size) {
  while (at + sizeof(std::uint64_t) <= size) {
    std::uint64_t word = 0;
    std::memcpy(&word, bytes + at, sizeof word);
    if ((word & kHighBits) != 0) break;
    at += sizeof word;
  }
  return at;
}

}  // namespace

bool Utf8Validator::feed(std::string_view text) {
  if (failed_) return false;
  const auto* bytes = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t size = text.size();
  std::size_t at = 0;
  while (at < size) {
    if (pending_ != 0) {
      const unsigned char byte = bytes[at++];
      if (byte < next_min_ || byte > next_max_) return fail();
      --pending_;
      next_min_ = 0x80;
      next_max_ = 0xBF;
      continue;
    }
    at = skip_ascii(bytes, at, size);
    if (at == size) break;
    const unsigned char lead = bytes[at++];
    if (lead < 0x80) continue;
    // RFC 3629 section 4: C0 and C1 only start overlong forms, F5..FF code points above U+10FFFF,
    // and 80..BF are continuation bytes with nothing to continue.
    if (lead < 0xC2 || lead > 0xF4) return fail();
    if (lead < 0xE0) {
      pending_ = 1;
    } else if (lead < 0xF0) {
      pending_ = 2;
      if (lead == 0xE0) next_min_ = 0xA0;  // below: an overlong three-byte form
      if (lead == 0xED) next_max_ = 0x9F;  // above: a surrogate
    } else {
      pending_ = 3;
      if (lead == 0xF0) next_min_ = 0x90;  // below: an overlong four-byte form
      if (lead == 0xF4) next_max_ = 0x8F;  // above: beyond U+10FFFF
    }
  }
  return true;
}

bool is_valid_utf8(std::string_view text) {
  Utf8Validator validator;
  return validator.feed(text) && validator.complete();
}

}  // namespace mobot::api
