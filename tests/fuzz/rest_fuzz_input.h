#pragma once

// The input format of the REST fuzz target (rest_bodies_fuzz.cpp), shared with the API test that
// replays its corpus against a real mobotd (tests/api/rest_fuzz_replay_test.cpp): records
// separated by NUL bytes, each a flags byte, the target, '\n', the body. The flags byte picks the
// method (bits 0-2), the credentials (bits 3-5), whether the fake robot refuses everything (bit 6,
// the fuzz target only) and which of two connections sends it (bit 7).

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace mobot::fuzz {

inline constexpr std::array<std::string_view, 8> kRestFuzzMethods{
    "GET", "POST", "PUT", "DELETE", "PATCH", "HEAD", "OPTIONS", "POST"};

// An Authorization header as a scheme and a credential. The credentials viewer, operator, admin
// and operator2 name tokens with those roles (the fakes' tokens in the fuzz target, real ones in
// the replay); the others are never valid.
struct RestFuzzCredential {
  std::string_view scheme;  // with its trailing space, if any
  std::string_view name;
  bool empty() const { return scheme.empty() && name.empty(); }
};
inline constexpr std::array<RestFuzzCredential, 8> kRestFuzzCredentials{
    {{"", ""},
     {"Bearer ", "viewer"},
     {"Bearer ", "operator"},
     {"Bearer ", "admin"},
     {"bearer ", "operator2"},
     {"Bearer ", "nobody"},
     {"Bearer", ""},
     {"Basic ", "b3BlcmF0b3I="}}};

inline constexpr std::size_t kRestFuzzMaxRecords = 4;

struct RestFuzzRecord {
  std::uint8_t flags = 0;
  std::string_view target;
  std::string_view body;

  std::string_view method() const { return kRestFuzzMethods[flags & 0x7U]; }
  const RestFuzzCredential& credential() const { return kRestFuzzCredentials[(flags >> 3) & 0x7U]; }
  bool fakes_refuse() const { return (flags & 0x40U) != 0; }
  unsigned connection() const { return (flags & 0x80U) != 0 ? 2U : 1U; }
  // Beast's parser only hands on targets of visible characters (RFC 9112 3.2): the others never
  // reach the router.
  bool target_reaches_router() const {
    for (const char c : target) {
      if (static_cast<unsigned char>(c) <= 0x20 || c == 0x7F) return false;
    }
    return true;
  }
};

// The first kRestFuzzMaxRecords records of an input; empty ones are skipped.
inline std::vector<RestFuzzRecord> rest_fuzz_records(std::string_view input) {
  std::vector<RestFuzzRecord> records;
  for (std::size_t record = 0; record < kRestFuzzMaxRecords && !input.empty(); ++record) {
    const std::size_t end = input.find('\0');
    const std::string_view bytes = input.substr(0, end);
    if (!bytes.empty()) {
      const std::string_view rest = bytes.substr(1);
      const std::size_t line_end = rest.find('\n');
      records.push_back(
          {static_cast<std::uint8_t>(bytes[0]), rest.substr(0, line_end),
           line_end == std::string_view::npos ? std::string_view{} : rest.substr(line_end + 1)});
    }
    if (end == std::string_view::npos) break;
    input.remove_prefix(end + 1);
  }
  return records;
}

}  // namespace mobot::fuzz
