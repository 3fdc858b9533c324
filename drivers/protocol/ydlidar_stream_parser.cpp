#include "drivers/protocol/ydlidar_stream_parser.h"

#include <algorithm>

namespace mobot::protocol::ydlidar {
namespace {

// What the largest single response the parser takes needs (device info).
constexpr std::size_t kMaxResponseBytes = kResponseHeaderBytes + kDeviceInfoBytes;

}  // namespace

StreamParser::StreamParser(Options options) : options_(options) {
  const std::size_t max_packet_bytes =
      kScanHeaderBytes + kMaxSamplesPerPacket * sample_bytes(options_.format);
  // Room for the longest item plus as much again, so that a large chunk goes through in few passes.
  capacity_ = 2 * std::max(max_packet_bytes, kMaxResponseBytes);
  buffer_.reserve(capacity_);
}

void StreamParser::feed(std::span<const std::uint8_t> bytes, std::vector<StreamItem>& items) {
  stats_.bytes += bytes.size();
  // In slices, so that the buffer stays bounded however large the chunk.
  while (!bytes.empty()) {
    const std::size_t room = capacity_ - buffer_.size();
    const std::size_t take = std::min(room, bytes.size());
    buffer_.insert(buffer_.end(), bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(take));
    bytes = bytes.subspan(take);
    parse(items);
  }
}

void StreamParser::reset() {
  stats_.discarded_bytes += buffer_.size();
  buffer_.clear();
}

void StreamParser::parse(std::vector<StreamItem>& items) {
  const std::span<const std::uint8_t> data(buffer_);
  std::size_t at = 0;
  const auto discard = [&](std::size_t count) {
    at += count;
    stats_.discarded_bytes += count;
  };
  while (data.size() - at >= 2) {
    const std::span<const std::uint8_t> rest = data.subspan(at);
    if (rest[0] == kPacketSync1 && rest[1] == kPacketSync2) {
      if (rest.size() < kScanHeaderBytes) break;
      const std::size_t count = rest[3];
      // Bit 0 of FSA and LSA is a check bit, always 1 (the SDK resyncs on it too).
      if (count == 0 || count > kMaxSamplesPerPacket || (rest[4] & 0x01) == 0 ||
          (rest[6] & 0x01) == 0) {
        discard(1);
        continue;
      }
      const std::size_t length = kScanHeaderBytes + count * sample_bytes(options_.format);
      if (rest.size() < length) break;
      const std::span<const std::uint8_t> packet = rest.first(length);
      const std::uint16_t sent_cs = static_cast<std::uint16_t>(packet[8] | (packet[9] << 8));
      if (scan_checksum(packet, options_.format) != sent_cs) {
        ++stats_.checksum_errors;
        discard(1);
        continue;
      }
      std::optional<ScanPacket> decoded = decode_scan_packet(packet, options_.format);
      if (!decoded) {
        discard(1);
        continue;
      }
      items.emplace_back(std::move(*decoded));
      ++stats_.scan_packets;
      at += length;
    } else if (rest[0] == kResponseSync1 && rest[1] == kResponseSync2) {
      if (rest.size() < kResponseHeaderBytes) break;
      const std::optional<ResponseHeader> header = decode_response_header(rest);
      if (!header || !is_known_response(*header)) {
        discard(1);
        continue;
      }
      const std::size_t payload_bytes =
          header->mode == ResponseMode::kSingle ? static_cast<std::size_t>(header->length) : 0;
      const std::size_t length = kResponseHeaderBytes + payload_bytes;
      if (rest.size() < length) break;
      const std::span<const std::uint8_t> payload =
          rest.subspan(kResponseHeaderBytes, payload_bytes);
      items.emplace_back(Response{*header, {payload.begin(), payload.end()}});
      ++stats_.responses;
      at += length;
    } else {
      // Skip to the next byte that could open an item.
      const auto next = std::find_if(rest.begin() + 1, rest.end(), [](std::uint8_t b) {
        return b == kPacketSync1 || b == kResponseSync1;
      });
      discard(static_cast<std::size_t>(next - rest.begin()));
    }
  }
  // A lone byte that cannot open an item need not wait for the next chunk.
  if (data.size() - at == 1 && data[at] != kPacketSync1 && data[at] != kResponseSync1) discard(1);
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(at));
}

}  // namespace mobot::protocol::ydlidar
