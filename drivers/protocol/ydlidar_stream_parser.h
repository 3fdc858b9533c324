#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <variant>
#include <vector>

#include "drivers/protocol/ydlidar_g4.h"

namespace mobot::protocol::ydlidar {

// A response as it came: the header and, for a single response, its payload (a continuous one,
// the start-scan answer, has none: scan packets follow it).
struct Response {
  ResponseHeader header;
  std::vector<std::uint8_t> payload;
};

using StreamItem = std::variant<Response, ScanPacket>;

// Cuts what the G4 sends into responses and scan packets, whatever the chunks the bytes arrive
// in. Between items it looks for the next AA 55 or A5 5A; a candidate that turns out wrong (an
// impossible header, an unknown response, a scan packet whose checksum fails) costs its first byte
// only and the search goes on from the next, so the packet that follows a damaged one is found
// whatever the damage did to its length. A packet with a wrong checksum is never yielded.
// The parser holds at most one item's worth of bytes between calls. Never throws.
class StreamParser {
 public:
  struct Options {
    SampleFormat format = SampleFormat::kDistance;
  };

  struct Stats {
    std::uint64_t bytes = 0;            // every byte fed
    std::uint64_t scan_packets = 0;     // good ones, yielded
    std::uint64_t responses = 0;        // yielded
    std::uint64_t checksum_errors = 0;  // scan packets dropped for their CS
    std::uint64_t discarded_bytes = 0;  // bytes that belonged to no yielded item
  };

  StreamParser() : StreamParser(Options{}) {}
  explicit StreamParser(Options options);

  // Appends the items completed by `bytes` to `items`.
  void feed(std::span<const std::uint8_t> bytes, std::vector<StreamItem>& items);
  // Drops a partial item (the next byte starts a fresh search); the counters stay.
  void reset();

  const Stats& stats() const { return stats_; }
  // Bytes kept for an item not yet complete: bytes == yielded items' bytes + discarded + this.
  std::size_t buffered_bytes() const { return buffer_.size(); }

 private:
  // Consumes what it can from buffer_, leaving a partial candidate at its front.
  void parse(std::vector<StreamItem>& items);

  Options options_;
  Stats stats_;
  std::vector<std::uint8_t> buffer_;
  std::size_t capacity_ = 0;
};

}  // namespace mobot::protocol::ydlidar
