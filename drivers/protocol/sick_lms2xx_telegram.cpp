#include "drivers/protocol/sick_lms2xx_telegram.h"

#include <algorithm>
#include <limits>

#include "drivers/protocol/sick_lms2xx_crc.h"

namespace mobot::protocol::sick {
namespace {

constexpr std::uint8_t kMeasuredValuesCommand = 0xB0;
constexpr std::uint8_t kReplyBit = 0x80;
// A device telegram has at least its command and status byte; a request at least its command.
constexpr std::size_t kMinReplyPayloadBytes = 2;
constexpr std::size_t kMinRequestPayloadBytes = 1;

std::uint16_t little_endian(std::uint8_t low, std::uint8_t high) {
  return static_cast<std::uint16_t>(low | (high << 8U));
}

}  // namespace

double transmission_time_s(std::size_t bytes, int baud_rate) {
  if (baud_rate <= 0) return 0.0;
  return static_cast<double>(bytes) * kBitsPerByte / static_cast<double>(baud_rate);
}

std::vector<std::uint8_t> encode_telegram(std::uint8_t address,
                                          std::span<const std::uint8_t> payload) {
  const std::size_t length =
      std::min<std::size_t>(payload.size(), std::numeric_limits<std::uint16_t>::max());
  std::vector<std::uint8_t> out;
  out.reserve(kHeaderBytes + length + kCrcBytes);
  out.push_back(kStx);
  out.push_back(address);
  out.push_back(static_cast<std::uint8_t>(length & 0xFFU));
  out.push_back(static_cast<std::uint8_t>(length >> 8U));
  out.insert(out.end(), payload.begin(), payload.begin() + static_cast<std::ptrdiff_t>(length));
  const std::uint16_t crc = crc16(out);
  out.push_back(static_cast<std::uint8_t>(crc & 0xFFU));
  out.push_back(static_cast<std::uint8_t>(crc >> 8U));
  return out;
}

std::optional<Telegram> parse_telegram(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kHeaderBytes + kCrcBytes || bytes[0] != kStx) return std::nullopt;
  const std::size_t length = little_endian(bytes[2], bytes[3]);
  if (bytes.size() != kHeaderBytes + length + kCrcBytes) return std::nullopt;
  const std::size_t crc_at = kHeaderBytes + length;
  if (crc16(bytes.first(crc_at)) != little_endian(bytes[crc_at], bytes[crc_at + 1])) {
    return std::nullopt;
  }
  Telegram telegram;
  telegram.address = bytes[1];
  telegram.payload.assign(bytes.begin() + kHeaderBytes,
                          bytes.begin() + static_cast<std::ptrdiff_t>(crc_at));
  return telegram;
}

TelegramStream::TelegramStream() : TelegramStream(StreamDirection::kFromLms) {}

TelegramStream::TelegramStream(StreamDirection direction)
    : TelegramStream(direction,
                     direction == StreamDirection::kFromLms ? kReplyAddress : kLmsAddress) {}

TelegramStream::TelegramStream(StreamDirection direction, std::uint8_t address)
    : direction_(direction), address_(address) {
  buffer_.reserve(kCapacityBytes);
}

void TelegramStream::reset() {
  stats_.discarded_bytes += buffer_.size();
  buffer_offset_ += buffer_.size();
  buffer_.clear();
}

std::vector<StreamEvent> TelegramStream::feed(std::span<const std::uint8_t> bytes) {
  std::vector<StreamEvent> events;
  stats_.bytes += bytes.size();
  // Whatever stays buffered after a parse is shorter than one telegram, so each round takes in at
  // least kCapacityBytes - kMaxTelegramBytes new bytes and the buffer stays within its capacity.
  while (!bytes.empty()) {
    const std::size_t take = std::min(bytes.size(), kCapacityBytes - buffer_.size());
    buffer_.insert(buffer_.end(), bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(take));
    bytes = bytes.subspan(take);
    parse(events);
  }
  return events;
}

TelegramStream::Candidate TelegramStream::check_candidate(std::size_t at,
                                                          std::size_t& telegram_bytes) const {
  const std::size_t available = buffer_.size() - at;
  if (available < 2) return Candidate::kWait;
  if (buffer_[at + 1] != address_) return Candidate::kReject;
  if (available < kHeaderBytes) return Candidate::kWait;
  const bool from_lms = direction_ == StreamDirection::kFromLms;
  const std::size_t length = little_endian(buffer_[at + 2], buffer_[at + 3]);
  const std::size_t min_length = from_lms ? kMinReplyPayloadBytes : kMinRequestPayloadBytes;
  if (length < min_length || length > kMaxPayloadBytes) return Candidate::kReject;
  if (from_lms) {
    if (available < kHeaderBytes + 1) return Candidate::kWait;
    const std::uint8_t command = buffer_[at + kHeaderBytes];
    if ((command & kReplyBit) == 0) return Candidate::kReject;
    if (command == kMeasuredValuesCommand) {
      // Command, value count (10 bits + flags), 2 bytes per value, up to 2 bytes of real-time
      // index, status: a false header rarely gets past this.
      if (available < kHeaderBytes + 3) return Candidate::kWait;
      const std::size_t values =
          little_endian(buffer_[at + kHeaderBytes + 1], buffer_[at + kHeaderBytes + 2]) & 0x3FFU;
      const std::size_t least = 1 + 2 + 2 * values + 1;
      if (length < least || length > least + 2) return Candidate::kReject;
    }
  }
  telegram_bytes = kHeaderBytes + length + kCrcBytes;
  if (available < telegram_bytes) return Candidate::kWait;
  return Candidate::kTelegram;
}

void TelegramStream::parse(std::vector<StreamEvent>& events) {
  const bool from_lms = direction_ == StreamDirection::kFromLms;
  std::size_t at = 0;
  while (at < buffer_.size()) {
    const std::uint8_t byte = buffer_[at];
    if (byte == kStx) {
      std::size_t telegram_bytes = 0;
      const Candidate candidate = check_candidate(at, telegram_bytes);
      if (candidate == Candidate::kWait) break;
      if (candidate == Candidate::kTelegram) {
        const std::span<const std::uint8_t> whole(buffer_.data() + at, telegram_bytes);
        const std::size_t crc_at = telegram_bytes - kCrcBytes;
        if (crc16(whole.first(crc_at)) == little_endian(whole[crc_at], whole[crc_at + 1])) {
          StreamEvent event;
          event.kind = StreamEvent::Kind::kTelegram;
          event.telegram.address = whole[1];
          event.telegram.payload.assign(whole.begin() + kHeaderBytes,
                                        whole.begin() + static_cast<std::ptrdiff_t>(crc_at));
          events.push_back(std::move(event));
          ++stats_.telegrams;
          stats_.telegram_bytes += telegram_bytes;
          at += telegram_bytes;
          continue;
        }
        ++stats_.crc_errors;
        events.push_back(StreamEvent{StreamEvent::Kind::kBadCrc, {}});
        controls_hidden_until_ =
            std::max<std::uint64_t>(controls_hidden_until_, buffer_offset_ + at + telegram_bytes);
      }
      ++stats_.discarded_bytes;
      ++at;
      continue;
    }
    const bool control = from_lms && (byte == kAckByte || byte == kNakByte) &&
                         buffer_offset_ + at >= controls_hidden_until_;
    if (control) {
      events.push_back(
          StreamEvent{byte == kAckByte ? StreamEvent::Kind::kAck : StreamEvent::Kind::kNak, {}});
      ++(byte == kAckByte ? stats_.acks : stats_.naks);
    } else {
      ++stats_.discarded_bytes;
    }
    ++at;
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(at));
  buffer_offset_ += at;
}

}  // namespace mobot::protocol::sick
