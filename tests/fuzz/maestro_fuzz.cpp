// Fuzzes the Pololu Maestro codec: the host's reply collector fed in chunks of varying size (and
// the same bytes one at a time, which must come to the same answers), and the Maestro's command
// parser (with and without CRC), whose every command must be one the host's builders make.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <span>
#include <vector>

#include "drivers/protocol/pololu_maestro.h"

namespace mx = mobot::protocol::maestro;

namespace {

void check(bool condition) {
  if (!condition) std::abort();
}

std::vector<mx::Query> queries_from(std::uint8_t selector) {
  std::vector<mx::Query> queries;
  const std::size_t count = selector % 6;
  for (std::size_t i = 0; i < count; ++i) {
    queries.push_back(static_cast<mx::Query>((selector >> (i % 4)) % 3));
  }
  return queries;
}

// The command the host's builders make for `parsed`.
mx::Packet rebuild(const mx::ParsedCommand& parsed) {
  switch (parsed.command) {
    case mx::Command::kSetTarget:
      return mx::set_target(parsed.channel, parsed.value);
    case mx::Command::kSetSpeed:
      return mx::set_speed(parsed.channel, parsed.value);
    case mx::Command::kSetAcceleration:
      return mx::set_acceleration(parsed.channel, parsed.value);
    case mx::Command::kGetPosition:
      return mx::get_position(parsed.channel);
    case mx::Command::kGetMovingState:
      return mx::get_moving_state();
    case mx::Command::kSetMultipleTargets:
      return mx::set_multiple_targets(parsed.channel, parsed.targets);
    case mx::Command::kGetErrors:
      return mx::get_errors();
    case mx::Command::kGoHome:
      return mx::go_home();
  }
  return {};
}

// A command the parser made is one the builders make, and it parses back to itself.
void check_command(const mx::ParsedCommand& parsed, bool crc) {
  check(parsed.channel < 0x80 && parsed.value <= mx::kMax14Bit);
  mx::Packet built = rebuild(parsed);
  if (crc) built = mx::with_crc(std::move(built));
  mx::CommandParser again(crc);
  std::optional<mx::CommandEvent> event;
  for (std::size_t i = 0; i < built.size(); ++i) {
    event = again.feed(built[i]);
    check(event.has_value() == (i + 1 == built.size()));
  }
  check(event && event->errors == 0 && event->command && *event->command == parsed);
}

void fuzz_parser(std::span<const std::uint8_t> bytes, bool crc) {
  mx::CommandParser parser(crc);
  for (std::uint8_t byte : bytes) {
    const std::optional<mx::CommandEvent> event = parser.feed(byte);
    if (!event) continue;
    check(event->command || event->errors != 0);
    check((event->errors & ~(mx::error_bit::kSerialProtocol | mx::error_bit::kSerialCrc)) == 0);
    if (event->command) check_command(*event->command, crc);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> input(data, size);
  if (input.size() < 1) return 0;
  mx::ReplyCollector chunked;
  mx::ReplyCollector bytewise;
  std::vector<mx::Query> queries = queries_from(input[0]);
  chunked.expect(queries);
  bytewise.expect(queries);
  std::vector<std::uint8_t> batch;  // the bytes since the last expect()

  std::size_t offset = 1;
  while (offset < input.size()) {
    // A chunk: its size from the first byte, then up to that many bytes.
    const std::uint8_t control = input[offset++];
    const std::size_t length = std::min<std::size_t>(control % 13, input.size() - offset);
    const std::span<const std::uint8_t> chunk = input.subspan(offset, length);
    offset += length;

    const mx::ReplyCollector::State after_chunk = chunked.feed(chunk);
    for (std::uint8_t byte : chunk) bytewise.feed(std::span<const std::uint8_t>(&byte, 1));
    batch.insert(batch.end(), chunk.begin(), chunk.end());
    check(after_chunk == bytewise.state());
    check(chunked.values() == bytewise.values());
    if (const auto values = chunked.values()) {
      // Whole: exactly the bytes of the answers, decoded in order.
      check(batch.size() == mx::reply_bytes(queries));
      check(*values == *mx::decode_replies(queries, batch));
      for (std::uint16_t value : *values) {
        (void)mx::plausible_servo_position(value);
        (void)mx::range_from_analog(value, mx::RangerScale{});
        if (const auto angle = mx::angle_for_position(mx::ServoCalibration{}, value)) {
          check(mx::target_for_angle(mx::ServoCalibration{}, *angle) ==
                std::min(value, mx::kMax14Bit));
        }
      }
    }
    if (after_chunk == mx::ReplyCollector::State::kWaiting) {
      check(batch.size() < mx::reply_bytes(queries));
    }

    // The Maestro's side: whatever the chunk is, what it takes for a command is a command.
    fuzz_parser(chunk, (control & 0x20) != 0);

    // Sometimes the host moves on to the next batch.
    if (control & 0x80) {
      queries = queries_from(control);
      chunked.expect(queries);
      bytewise.expect(queries);
      batch.clear();
    } else if (control & 0x40) {
      chunked.cancel();
      bytewise.cancel();
      batch.clear();
    }
  }

  const mx::ReplyCollector::Counters& counters = bytewise.counters();
  check(chunked.counters().bytes == counters.bytes);
  check(chunked.counters().batches == counters.batches);
  check(chunked.counters().abandoned == counters.abandoned);
  // A chunk that overran after the batch was whole counts once, as a run of single bytes does.
  check(chunked.counters().overruns == counters.overruns);
  return 0;
}
