// libFuzzer target for the SICK LMS2xx codec: the input is a byte stream from the laser, fed to
// the host's stream parser in chunks whose sizes the input chooses; every telegram found goes
// through the reply parsers, the measured-values decoder, the interlace assembler and the
// conversion to a LaserScan. The input as one payload goes to the decoders directly too. Any
// crash, sanitizer report or broken invariant (a trap) is a finding.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "drivers/protocol/sick_lms2xx_commands.h"
#include "drivers/protocol/sick_lms2xx_scan.h"
#include "drivers/protocol/sick_lms2xx_telegram.h"

namespace {

namespace sick = mobot::protocol::sick;

void check(bool condition) {
  if (!condition) __builtin_trap();
}

void check_accounting(const sick::TelegramStream& stream) {
  const sick::StreamStats& s = stream.stats();
  check(stream.buffered() <= sick::TelegramStream::kCapacityBytes);
  check(s.bytes == s.telegram_bytes + s.acks + s.naks + s.discarded_bytes + stream.buffered());
}

void convert(const sick::MeasuredValues& values, int range_bits) {
  sick::LaserScanOptions options;
  options.range_bits = range_bits;
  const auto scan = sick::to_laser_scan(values, options);
  if (!scan) return;
  check(scan->ranges_m.size() == values.values.size());
  for (const float range_m : scan->ranges_m) check(range_m >= 0.0F);
}

struct Decoders {
  std::array<sick::InterlacedScanAssembler, 3> assemblers{
      sick::InterlacedScanAssembler(sick::AngularResolution::kOneDeg),
      sick::InterlacedScanAssembler(sick::AngularResolution::kHalfDeg),
      sick::InterlacedScanAssembler(sick::AngularResolution::kQuarterDeg)};

  void telegram(const sick::Telegram& telegram, int range_bits) {
    // A telegram frames and parses back to itself.
    if (telegram.payload.size() <= sick::kMaxPayloadBytes) {
      const auto again =
          sick::parse_telegram(sick::encode_telegram(telegram.address, telegram.payload));
      check(again.has_value() && *again == telegram);
    }

    (void)sick::parse_mode_switch_reply(telegram);
    if (const auto variant = sick::parse_variant_reply(telegram)) (void)variant->variant();
    if (const auto status = sick::parse_status_reply(telegram)) (void)status->units();

    const auto values = sick::decode_measured_values(telegram);
    if (!values) return;
    check(values->values.size() <= sick::kMaxValues);
    // Encoding what was decoded decodes to the same (a one-byte real-time index aside).
    if (!values->real_time_index || *values->real_time_index <= 0xFF) {
      const auto reencoded = sick::parse_telegram(sick::measured_values_telegram(*values));
      check(reencoded.has_value() && sick::decode_measured_values(*reencoded) == values);
    }
    convert(*values, range_bits);
    for (sick::InterlacedScanAssembler& assembler : assemblers) {
      if (const auto scan = assembler.add(*values)) {
        check(scan->values.size() <= sick::kMaxValues);
        convert(*scan, range_bits);
      }
    }
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::span<const std::uint8_t> input(data, size);
  const int range_bits = 12 + (input[0] % 6);  // 12..17: two widths no measuring mode has
  const std::uint8_t chunk_seed = input[1];
  const std::span<const std::uint8_t> stream_bytes = input.subspan(2);

  Decoders decoders;
  sick::TelegramStream from_lms;
  sick::TelegramStream to_lms(sick::StreamDirection::kToLms);
  std::size_t at = 0;
  std::size_t round = 0;
  while (at < stream_bytes.size()) {
    // Chunk sizes from 0 to 255 bytes, varying with the seed and the data.
    std::size_t chunk = static_cast<std::uint8_t>(chunk_seed * (round + 1) + stream_bytes[at]) %
                        (round % 3 == 0 ? 7U : 256U);
    if (chunk == 0) {
      check(from_lms.feed({}).empty());
      chunk = 1;
    }
    const std::span<const std::uint8_t> piece =
        stream_bytes.subspan(at, std::min(chunk, stream_bytes.size() - at));
    for (const sick::StreamEvent& event : from_lms.feed(piece)) {
      if (event.kind == sick::StreamEvent::Kind::kTelegram) {
        decoders.telegram(event.telegram, range_bits);
      }
    }
    for (const sick::StreamEvent& event : to_lms.feed(piece)) {
      check(event.kind == sick::StreamEvent::Kind::kTelegram ||
            event.kind == sick::StreamEvent::Kind::kBadCrc);
    }
    check_accounting(from_lms);
    check_accounting(to_lms);
    at += piece.size();
    ++round;
  }
  check(from_lms.stats().bytes == stream_bytes.size());

  // The input as a payload, straight to the decoders.
  decoders.telegram(
      sick::Telegram{sick::kReplyAddress,
                     std::vector<std::uint8_t>(stream_bytes.begin(), stream_bytes.end())},
      range_bits);
  return 0;
}
