#include "drivers/protocol/line_framer.h"

namespace mobot::protocol {

void LineFramer::feed(std::span<const std::uint8_t> bytes, std::vector<std::string>& lines) {
  for (const std::uint8_t byte : bytes) {
    if (byte == '\n' || (options_.cr_ends_line && byte == '\r')) {
      end_line(lines);
    } else if (byte == '\r') {
      // CR of a CR LF pair: the LF ends the line.
    } else if (byte < 0x20 || byte > 0x7E || partial_.size() >= options_.max_line_bytes) {
      spoiled_ = true;
    } else if (!spoiled_) {
      partial_.push_back(static_cast<char>(byte));
    }
  }
}

void LineFramer::end_line(std::vector<std::string>& lines) {
  if (spoiled_) {
    ++garbage_lines_;
  } else if (!partial_.empty()) {
    ++lines_;
    lines.push_back(partial_);
  }
  reset();
}

void LineFramer::reset() {
  partial_.clear();
  spoiled_ = false;
}

}  // namespace mobot::protocol
