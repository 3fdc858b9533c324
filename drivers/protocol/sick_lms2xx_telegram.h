#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace mobot::protocol::sick {

// An LMS2xx telegram on RS-232, both directions:
//   STX 0x02 | address | length (2 bytes, low first) | payload | CRC-16 (2 bytes, low first)
// The payload is the command byte and its data; in the device's telegrams a status byte ends it.
// The length field counts the payload. The host writes to the LMS's address (0 unless configured
// otherwise); the LMS answers from that address with the top bit set. Before each reply telegram
// the LMS sends a lone ACK byte, or a lone NAK when the host's telegram arrived damaged.
inline constexpr std::uint8_t kStx = 0x02;
inline constexpr std::uint8_t kAckByte = 0x06;
inline constexpr std::uint8_t kNakByte = 0x15;
inline constexpr std::uint8_t kLmsAddress = 0x00;
inline constexpr std::uint8_t kReplyAddress = 0x80;

inline constexpr std::size_t kHeaderBytes = 4;
inline constexpr std::size_t kCrcBytes = 2;
// The largest telegram an LMS2xx sends: 721 measured values (2 bytes each) behind the command and
// the value count, a real-time index of up to 2 bytes and the status byte.
inline constexpr std::size_t kMaxPayloadBytes = 1 + 2 + 2 * 721 + 2 + 1;
inline constexpr std::size_t kMaxTelegramBytes = kHeaderBytes + kMaxPayloadBytes + kCrcBytes;

// 8N1 framing: a start and a stop bit around each byte.
inline constexpr double kBitsPerByte = 10.0;
// How long `bytes` occupy the line at `baud_rate` (0 for a non-positive rate).
double transmission_time_s(std::size_t bytes, int baud_rate);

struct Telegram {
  std::uint8_t address = 0;
  std::vector<std::uint8_t> payload;  // command byte first; a device's telegram ends with status

  std::uint8_t command() const { return payload.empty() ? 0 : payload.front(); }
  // Meaningful for the device's telegrams only.
  std::uint8_t status() const { return payload.empty() ? 0 : payload.back(); }

  bool operator==(const Telegram&) const = default;
};

// The complete telegram, CRC included. A payload longer than the length field can say is cut to
// 65535 bytes (no LMS command comes close).
std::vector<std::uint8_t> encode_telegram(std::uint8_t address,
                                          std::span<const std::uint8_t> payload);

// Exactly one telegram, any address: nullopt unless STX, the length and the CRC all agree with
// `bytes`' size and content.
std::optional<Telegram> parse_telegram(std::span<const std::uint8_t> bytes);

// What the stream parser found, in stream order. kBadCrc carries no telegram: a telegram whose
// CRC fails is never handed on (a device model answers it with NAK; a host may retry early).
struct StreamEvent {
  enum class Kind { kTelegram, kAck, kNak, kBadCrc };
  Kind kind = Kind::kTelegram;
  Telegram telegram;  // kTelegram only
};

// Every byte fed ends in exactly one of telegram_bytes, acks, naks, discarded_bytes or, while it
// waits for the rest of a telegram, buffered().
struct StreamStats {
  std::uint64_t bytes = 0;
  std::uint64_t telegrams = 0;
  std::uint64_t telegram_bytes = 0;
  std::uint64_t crc_errors = 0;
  std::uint64_t acks = 0;
  std::uint64_t naks = 0;
  std::uint64_t discarded_bytes = 0;
};

enum class StreamDirection {
  // Host side: telegrams from the LMS (address 0x80, status byte, command with the top bit set),
  // lone ACK/NAK bytes between them reported.
  kFromLms,
  // Device side (an emulated LMS): the host's requests to address 0, no ACK/NAK.
  kToLms,
};

// Finds telegrams in a byte stream fed in arbitrary pieces. A candidate needs STX, the expected
// address and a plausible length (for a measured-values telegram: the length its value count
// implies); anything else is discarded a byte at a time, so after garbage, a lost byte or a
// false STX the parser resynchronises at the next STX. A candidate whose CRC fails is dropped the
// same way (the search resumes at the byte after its STX) and ACK/NAK bytes inside its extent are
// not reported, since they were more likely its payload than a real reply. The buffer never holds
// more than two of the largest telegrams; no input makes it throw.
class TelegramStream {
 public:
  static constexpr std::size_t kCapacityBytes = 2 * kMaxTelegramBytes;

  TelegramStream();
  explicit TelegramStream(StreamDirection direction);
  TelegramStream(StreamDirection direction, std::uint8_t address);

  std::vector<StreamEvent> feed(std::span<const std::uint8_t> bytes);

  const StreamStats& stats() const { return stats_; }
  // Bytes held because they may begin a telegram not complete yet.
  std::size_t buffered() const { return buffer_.size(); }
  // Forgets the buffered bytes (counted as discarded), e.g. after the host changed its baud rate.
  void reset();

 private:
  enum class Candidate { kTelegram, kWait, kReject };
  Candidate check_candidate(std::size_t at, std::size_t& telegram_bytes) const;
  void parse(std::vector<StreamEvent>& events);

  StreamDirection direction_;
  std::uint8_t address_;
  std::vector<std::uint8_t> buffer_;
  std::uint64_t buffer_offset_ = 0;          // stream offset of buffer_[0]
  std::uint64_t controls_hidden_until_ = 0;  // stream offset: no ACK/NAK reported before it
  StreamStats stats_;
};

}  // namespace mobot::protocol::sick
