// Fuzzes the Motion Mind codec: the host's reply parser fed in chunks of varying size (and the
// same bytes one at a time, which must come to the same replies), and the board's command
// parser, whose every accepted command must be one the host's builders make.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <span>
#include <vector>

#include "drivers/protocol/motion_mind.h"

namespace mm = mobot::protocol::motion_mind;

namespace {

void check(bool condition) {
  if (!condition) std::abort();
}

mm::ExpectedReply shape_from(std::uint8_t selector, std::uint8_t address) {
  switch (selector % 4) {
    case 0:
      return mm::ack_reply();
    case 1:
      return mm::motion_reply(address, static_cast<std::uint16_t>(selector >> 2));
    case 2:
      return mm::read_register_reply(address, static_cast<mm::Register>((selector >> 2) % 32));
    default:
      return mm::read_reply(address, 0x00010001u << ((selector >> 2) % 16));
  }
}

// The command the host's builders make for `parsed`, when they can make it unchanged.
std::optional<mm::Packet> rebuild(const mm::ParsedCommand& parsed) {
  switch (parsed.command) {
    case mm::Command::kChangeSpeed:
      if (parsed.value < -1023 || parsed.value > 1023) return std::nullopt;
      return mm::change_speed(parsed.address, static_cast<int>(parsed.value));
    case mm::Command::kMoveToAbsolute:
      return mm::move_to_absolute(parsed.address, static_cast<std::int32_t>(parsed.value));
    case mm::Command::kMoveToRelative:
      return mm::move_to_relative(parsed.address, static_cast<std::int32_t>(parsed.value));
    case mm::Command::kMoveAtVelocity:
      return mm::move_at_velocity(parsed.address, static_cast<int>(parsed.value));
    case mm::Command::kWrite:
    case mm::Command::kWriteStore: {
      const mm::RegisterInfo& info = mm::register_info(parsed.reg);
      if (info.writable && (parsed.value < info.min_value || parsed.value > info.max_value)) {
        return std::nullopt;
      }
      return parsed.command == mm::Command::kWrite
                 ? mm::write_register(parsed.address, parsed.reg, parsed.value)
                 : mm::write_store_register(parsed.address, parsed.reg, parsed.value);
    }
    case mm::Command::kRead:
      return mm::read_registers(parsed.address, parsed.mask);
    case mm::Command::kRestore:
      return mm::restore_defaults(parsed.address);
    case mm::Command::kReset:
      return mm::reset(parsed.address);
    case mm::Command::kReadRegister:
      return mm::read_register(parsed.address, parsed.reg);
  }
  return std::nullopt;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> input(data, size);
  if (input.size() < 2) return 0;
  mm::ReplyParser chunked;
  mm::ReplyParser bytewise;
  mm::ExpectedReply expected = shape_from(input[0], input[1]);
  chunked.expect(expected);
  bytewise.expect(expected);
  std::vector<std::uint8_t> seen;
  std::uint64_t reply_bytes_total = 0;

  std::size_t offset = 2;
  while (offset < input.size()) {
    // A chunk: its size from the first byte, then up to that many bytes.
    const std::uint8_t control = input[offset++];
    const std::size_t length = std::min<std::size_t>(control % 17, input.size() - offset);
    const std::span<const std::uint8_t> chunk = input.subspan(offset, length);
    offset += length;

    const std::optional<mm::Reply> from_chunk = chunked.feed(chunk);
    std::optional<mm::Reply> from_bytes;
    for (std::uint8_t byte : chunk) {
      seen.push_back(byte);
      std::optional<mm::Reply> reply = bytewise.feed(std::span<const std::uint8_t>(&byte, 1));
      if (!reply) continue;
      // A reply is exactly the last bytes seen, and its checksum holds.
      if (reply->ack) {
        check(expected.ack && seen.back() == mm::kAck);
        reply_bytes_total += 1;
      } else {
        check(!expected.ack && reply->address == expected.address &&
              reply->data.size() == expected.data_bytes);
        const mm::Packet wire = mm::encode_data_reply(reply->address, reply->data);
        check(seen.size() >= wire.size());
        check(std::equal(wire.begin(), wire.end(), seen.end() - static_cast<long>(wire.size())));
        reply_bytes_total += wire.size();
        (void)mm::decode_motion_reply(static_cast<std::uint16_t>(control), reply->data);
        (void)mm::register_value(0xFFFFFFFFu, static_cast<mm::Register>(control % 32), reply->data);
      }
      check(!from_bytes);
      from_bytes = std::move(reply);
    }
    check(from_chunk.has_value() == from_bytes.has_value());
    if (from_chunk) check(from_chunk->data == from_bytes->data);

    // The board's side: whatever the chunk is, a command it accepts is one the host can build.
    if (const std::optional<mm::ParsedCommand> parsed = mm::parse_command(chunk)) {
      const std::optional<mm::Packet> built = rebuild(*parsed);
      if (built) check(std::equal(built->begin(), built->end(), chunk.begin(), chunk.end()));
    }

    // Sometimes the host moves on to the next command.
    if (control & 0x80) {
      expected = shape_from(control, chunk.empty() ? input[1] : chunk.front());
      chunked.expect(expected);
      bytewise.expect(expected);
    } else if (control & 0x40) {
      chunked.cancel();
      bytewise.cancel();
    }
  }

  const mm::ReplyParser::Counters& counters = bytewise.counters();
  check(counters.bytes == counters.discarded_bytes + reply_bytes_total + bytewise.pending_bytes());
  check(chunked.counters().bytes == counters.bytes);
  check(chunked.counters().replies == counters.replies);
  check(chunked.counters().checksum_errors == counters.checksum_errors);
  check(chunked.counters().discarded_bytes == counters.discarded_bytes);
  return 0;
}
