// libFuzzer target: whatever bytes come down the line, the G4 stream parser, the scan assembler
// and the laser-scan conversion neither crash nor throw, keep their buffer bounded, and account
// for every byte.
//
// The input's first byte picks the sample format and the bin count, the next eight the sizes of
// the chunks the rest is fed in (cycled), as reads from a serial port would cut it.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <variant>
#include <vector>

#include "drivers/protocol/ydlidar_g4.h"
#include "drivers/protocol/ydlidar_scan.h"
#include "drivers/protocol/ydlidar_stream_parser.h"

namespace {

namespace yd = mobot::protocol::ydlidar;

constexpr std::size_t kChunkTableBytes = 8;

void check(bool ok) {
  if (!ok) __builtin_trap();
}

std::size_t item_bytes(const yd::StreamItem& item, yd::SampleFormat format) {
  if (const auto* response = std::get_if<yd::Response>(&item)) {
    return yd::kResponseHeaderBytes + response->payload.size();
  }
  return yd::kScanHeaderBytes +
         std::get<yd::ScanPacket>(item).samples.size() * yd::sample_bytes(format);
}

void check_scan(const yd::Scan& scan, int bin_count) {
  yd::LaserScanOptions options;
  options.bin_count = bin_count;
  const mobot::msgs::LaserScan laser = yd::to_laser_scan(scan, options, 0.0);
  check(laser.ranges_m.size() == static_cast<std::size_t>(bin_count));
  for (const float range_m : laser.ranges_m) {
    // A return in range, or one of the two no-return values.
    check(range_m == 0.0F || std::isinf(range_m) ||
          (range_m >= laser.range_min_m && range_m <= laser.range_max_m));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1 + kChunkTableBytes) return 0;
  const std::span<const std::uint8_t> input(data, size);
  const auto format = static_cast<yd::SampleFormat>(input[0] % 3);
  const int bin_count = 1 + (input[0] >> 2) * 23;  // 1 .. 1450
  const std::span<const std::uint8_t> chunk_table = input.subspan(1, kChunkTableBytes);
  std::span<const std::uint8_t> rest = input.subspan(1 + kChunkTableBytes);

  yd::StreamParser parser({format});
  yd::ScanAssembler assembler;
  std::vector<yd::StreamItem> items;
  std::uint64_t yielded_bytes = 0;
  const std::size_t max_item_bytes =
      yd::kScanHeaderBytes + yd::kMaxSamplesPerPacket * yd::sample_bytes(format);
  for (std::size_t turn = 0; !rest.empty(); ++turn) {
    // 1..256 bytes: from single bytes to more than the largest packet (250 bytes).
    const std::size_t chunk =
        std::min<std::size_t>(rest.size(), 1 + chunk_table[turn % kChunkTableBytes]);
    items.clear();
    parser.feed(rest.first(chunk), items);
    rest = rest.subspan(chunk);
    check(parser.buffered_bytes() < max_item_bytes);
    for (const yd::StreamItem& item : items) {
      yielded_bytes += item_bytes(item, format);
      if (const auto* response = std::get_if<yd::Response>(&item)) {
        check(yd::is_known_response(response->header));
        (void)yd::decode_device_info(response->payload);
        (void)yd::decode_health(response->payload);
        (void)yd::decode_scan_frequency_hz(response->payload);
        (void)yd::decode_sampling_rate_hz(response->payload);
        continue;
      }
      const auto& packet = std::get<yd::ScanPacket>(item);
      for (const yd::Sample& sample : packet.samples) {
        check(sample.angle_deg >= 0.0 && sample.angle_deg < 360.0);
        check(sample.range_m >= 0.0 && sample.range_m < 16.39);
      }
      if (const auto scan = assembler.add(packet)) check_scan(*scan, bin_count);
    }
  }
  const auto& stats = parser.stats();
  check(stats.bytes == size - 1 - kChunkTableBytes);
  check(stats.bytes == yielded_bytes + stats.discarded_bytes + parser.buffered_bytes());
  return 0;
}
