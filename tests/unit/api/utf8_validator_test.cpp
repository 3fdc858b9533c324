// The UTF-8 check of WebSocket text: Markus Kuhn's decoder stress cases (as Autobahn's 6.x cases
// use them), every code point, and the same bytes fed in pieces split anywhere.
#include "api/utf8_validator.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace mobot::api {
namespace {

std::string utf8(std::uint32_t code_point) {
  std::string out;
  if (code_point < 0x80) {
    out.push_back(static_cast<char>(code_point));
  } else if (code_point < 0x800) {
    out.push_back(static_cast<char>(0xC0 | (code_point >> 6)));
    out.push_back(static_cast<char>(0x80 | (code_point & 0x3F)));
  } else if (code_point < 0x10000) {
    out.push_back(static_cast<char>(0xE0 | (code_point >> 12)));
    out.push_back(static_cast<char>(0x80 | ((code_point >> 6) & 0x3F)));
    out.push_back(static_cast<char>(0x80 | (code_point & 0x3F)));
  } else {
    out.push_back(static_cast<char>(0xF0 | (code_point >> 18)));
    out.push_back(static_cast<char>(0x80 | ((code_point >> 12) & 0x3F)));
    out.push_back(static_cast<char>(0x80 | ((code_point >> 6) & 0x3F)));
    out.push_back(static_cast<char>(0x80 | (code_point & 0x3F)));
  }
  return out;
}

const std::vector<std::string> kValid = {
    "",
    "hello$world",
    "hello\xC2\xA2world",
    "hello\xE2\x82\xACworld",
    "hello\xF0\xA4\xAD\xA2world",
    // "kosme"
    "\xCE\xBA\xE1\xBD\xB9\xCF\x83\xCE\xBC\xCE\xB5",
    std::string(1, '\0'),
    // The first and the last code point of each length.
    "\xC2\x80",
    "\xE0\xA0\x80",
    "\xF0\x90\x80\x80",
    "\x7F",
    "\xDF\xBF",
    "\xEF\xBF\xBF",
    "\xF4\x8F\xBF\xBF",
    // Around the surrogates, and U+FFFD.
    "\xED\x9F\xBF",
    "\xEE\x80\x80",
    "\xEF\xBF\xBD",
    // Non-characters are UTF-8.
    "\xEF\xBF\xBE",
    "\xF0\x9F\xBF\xBF",
    "\xF3\xBF\xBF\xBE",
};

const std::vector<std::string> kInvalid = {
    // 5 and 6 byte forms, and code points beyond U+10FFFF.
    "\xF8\x88\x80\x80\x80",
    "\xFC\x84\x80\x80\x80\x80",
    "\xF7\xBF\xBF\xBF",
    "\xF4\x90\x80\x80",
    // Continuation bytes with nothing to continue.
    "\x80",
    "\xBF",
    "\x80\xBF",
    "\x80\xBF\x80\xBF",
    // Lonely start bytes, and sequences cut short.
    "\xC0 ",
    "\xE0 ",
    "\xF0 ",
    "\xF8 ",
    "\xFC ",
    "\xC0",
    "\xE0\x80",
    "\xF0\x80\x80",
    "\xDF",
    "\xEF\xBF",
    "\xF7\xBF\xBF",
    // Impossible bytes.
    "\xFE",
    "\xFF",
    "\xFE\xFE\xFF\xFF",
    // Overlong forms: of '/', the longest ones, and of NUL.
    "\xC0\xAF",
    "\xE0\x80\xAF",
    "\xF0\x80\x80\xAF",
    "\xC1\xBF",
    "\xE0\x9F\xBF",
    "\xF0\x8F\xBF\xBF",
    "\xC0\x80",
    "\xE0\x80\x80",
    "\xF0\x80\x80\x80",
    // UTF-16 surrogates, alone and paired.
    "\xED\xA0\x80",
    "\xED\xAD\xBF",
    "\xED\xBF\xBF",
    "\xED\xA0\x80\xED\xB0\x80",
    "\xED\xAF\xBF\xED\xBF\xBF",
    // Autobahn 6.3.1: valid text, then a surrogate.
    "\xCE\xBA\xE1\xBD\xB9\xCF\x83\xCE\xBC\xCE\xB5\xED\xA0\x80"
    "edited",
};

TEST(Utf8Validator, AcceptsKuhnsValidSequences) {
  for (const auto& text : kValid)
    EXPECT_TRUE(is_valid_utf8(text)) << ::testing::PrintToString(text);
}

TEST(Utf8Validator, RejectsKuhnsInvalidSequences) {
  for (const auto& text : kInvalid) {
    EXPECT_FALSE(is_valid_utf8(text)) << ::testing::PrintToString(text);
  }
}

TEST(Utf8Validator, AcceptsEveryCodePointButTheSurrogates) {
  for (std::uint32_t code_point = 0; code_point <= 0x10FFFF; ++code_point) {
    const bool surrogate = code_point >= 0xD800 && code_point <= 0xDFFF;
    ASSERT_EQ(is_valid_utf8(utf8(code_point)), !surrogate) << std::hex << code_point;
  }
}

TEST(Utf8Validator, ACodePointSplitAcrossPiecesIsValid) {
  const std::string text = "a\xC2\xA2 \xE2\x82\xAC \xF0\xA4\xAD\xA2 \xCE\xBA\xE1\xBD\xB9";
  for (std::size_t first = 0; first <= text.size(); ++first) {
    for (std::size_t second = first; second <= text.size(); ++second) {
      Utf8Validator validator;
      ASSERT_TRUE(validator.feed(text.substr(0, first)));
      ASSERT_TRUE(validator.feed(text.substr(first, second - first)));
      ASSERT_TRUE(validator.feed(text.substr(second)));
      EXPECT_TRUE(validator.complete()) << first << " " << second;
    }
  }
}

TEST(Utf8Validator, APieceEndingInsideACodePointIsNotComplete) {
  Utf8Validator validator;
  EXPECT_TRUE(validator.feed("ab\xF0\xA4"));
  EXPECT_FALSE(validator.complete());
  EXPECT_TRUE(validator.feed("\xAD"));
  EXPECT_FALSE(validator.complete());
  EXPECT_TRUE(validator.feed("\xA2"));
  EXPECT_TRUE(validator.complete());
}

TEST(Utf8Validator, FailsAtTheFirstBadByteAndStaysFailed) {
  // Autobahn's incremental case: "edited" then a surrogate, which fails on its second byte.
  Utf8Validator validator;
  EXPECT_TRUE(validator.feed("\x65\x64\x69\x74\x65\x64\xED"));
  EXPECT_FALSE(validator.feed("\xA0\x80"));
  EXPECT_FALSE(validator.feed("plain ascii"));
  EXPECT_FALSE(validator.complete());
  validator.reset();
  EXPECT_TRUE(validator.feed("plain ascii"));
  EXPECT_TRUE(validator.complete());
}

TEST(Utf8Validator, FindsABadByteAnywhereInLongAsciiText) {
  // The ASCII fast path checks eight bytes at once: a bad byte at any offset of a word is found.
  for (std::size_t at = 0; at < 40; ++at) {
    std::string text(40, 'x');
    text[at] = '\xFF';
    EXPECT_FALSE(is_valid_utf8(text)) << at;
    text[at] = '\xC3';
    if (at + 1 < text.size()) text[at + 1] = '\xA9';  // é
    EXPECT_EQ(is_valid_utf8(text), at + 1 < text.size()) << at;
  }
}

}  // namespace
}  // namespace mobot::api
