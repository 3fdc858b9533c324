#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace mobot::protocol {

// Cuts a byte stream of a line protocol into lines: a line ends at LF (a CR before it is dropped)
// or, when `cr_ends_line`, at a CR alone (a device's side reads commands that end in CR). A line
// longer than max_line_bytes, or one holding a byte that is not printable ASCII, is garbage: it is
// counted and dropped up to its end, so one burst of noise costs one line, not the stream.
class LineFramer {
 public:
  struct Options {
    std::size_t max_line_bytes = 64;
    bool cr_ends_line = false;
  };

  LineFramer() : LineFramer(Options{}) {}
  explicit LineFramer(Options options) : options_(options) {}

  // Appends the complete lines found in `bytes` to `lines`.
  void feed(std::span<const std::uint8_t> bytes, std::vector<std::string>& lines);
  // Forgets a partial line (after a time-out: what follows starts a new reply).
  void reset();

  std::uint64_t lines() const { return lines_; }
  std::uint64_t garbage_lines() const { return garbage_lines_; }

 private:
  void end_line(std::vector<std::string>& lines);

  Options options_;
  std::string partial_;
  bool spoiled_ = false;
  std::uint64_t lines_ = 0;
  std::uint64_t garbage_lines_ = 0;
};

}  // namespace mobot::protocol
