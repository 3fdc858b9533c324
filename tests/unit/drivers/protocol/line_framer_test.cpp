#include "drivers/protocol/line_framer.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace mobot::protocol {
namespace {

std::span<const std::uint8_t> bytes(const std::string& text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

TEST(LineFramer, CutsCrLfLinesAndDropsTheCr) {
  LineFramer framer;
  std::vector<std::string> lines;
  framer.feed(bytes("OK\r\n12 -7\r\n"), lines);
  EXPECT_EQ(lines, (std::vector<std::string>{"OK", "12 -7"}));
}

TEST(LineFramer, JoinsALineSplitAcrossReadsOneByteAtATime) {
  LineFramer framer;
  std::vector<std::string> lines;
  for (const char c : std::string("1234 5678\r\n")) {
    framer.feed(bytes(std::string(1, c)), lines);
  }
  EXPECT_EQ(lines, (std::vector<std::string>{"1234 5678"}));
}

TEST(LineFramer, CrEndsACommandOnTheDeviceSide) {
  LineFramer framer({.max_line_bytes = 64, .cr_ends_line = true});
  std::vector<std::string> lines;
  framer.feed(bytes("e\rm 10 10\r"), lines);
  EXPECT_EQ(lines, (std::vector<std::string>{"e", "m 10 10"}));
}

TEST(LineFramer, DropsALineWithANonPrintableByteAndKeepsTheNext) {
  LineFramer framer;
  std::vector<std::string> lines;
  framer.feed(bytes(std::string("1\x00"
                                "2 3\r\n4 5\r\n",
                                12)),
              lines);
  EXPECT_EQ(lines, (std::vector<std::string>{"4 5"}));
  EXPECT_EQ(framer.garbage_lines(), 1U);
}

TEST(LineFramer, DropsAnOverlongLineUpToItsEnd) {
  LineFramer framer({.max_line_bytes = 8, .cr_ends_line = false});
  std::vector<std::string> lines;
  framer.feed(bytes("0123456789abcdef\r\nOK\r\n"), lines);
  EXPECT_EQ(lines, (std::vector<std::string>{"OK"}));
  EXPECT_EQ(framer.garbage_lines(), 1U);
}

TEST(LineFramer, ResetForgetsAPartialLine) {
  LineFramer framer;
  std::vector<std::string> lines;
  framer.feed(bytes("12 3"), lines);
  framer.reset();
  framer.feed(bytes("OK\r\n"), lines);
  EXPECT_EQ(lines, (std::vector<std::string>{"OK"}));
}

}  // namespace
}  // namespace mobot::protocol
