#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace mobot::emulate {

// The replies a board has composed and the time each leaves the line: a reply is sent whole once
// its time has come (the board's processing delay plus its bytes at the baud rate), in order.
class TimedReplies {
 public:
  void push(double due_s, std::string text) { pending_.push_back({due_s, std::move(text)}); }
  // The bytes of every reply due by `now_s`.
  std::vector<std::uint8_t> take_due(double now_s);

 private:
  struct Reply {
    double due_s;
    std::string text;
  };
  std::vector<Reply> pending_;
};

}  // namespace mobot::emulate
