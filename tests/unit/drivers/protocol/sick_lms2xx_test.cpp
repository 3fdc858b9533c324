#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "drivers/protocol/sick_lms2xx_commands.h"
#include "drivers/protocol/sick_lms2xx_crc.h"
#include "drivers/protocol/sick_lms2xx_scan.h"
#include "drivers/protocol/sick_lms2xx_telegram.h"

namespace mobot::protocol::sick {
namespace {

using Bytes = std::vector<std::uint8_t>;
using Kind = StreamEvent::Kind;

constexpr double kDeg = std::numbers::pi / 180.0;

Bytes join(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const Bytes& part : parts) out.insert(out.end(), part.begin(), part.end());
  return out;
}

std::uint16_t crc_of(const Bytes& telegram) {
  return crc16(std::span<const std::uint8_t>(telegram).first(telegram.size() - 2));
}

std::uint16_t crc_field(const Bytes& telegram) {
  return static_cast<std::uint16_t>(telegram[telegram.size() - 2] |
                                    (telegram[telegram.size() - 1] << 8U));
}

std::vector<Kind> kinds(const std::vector<StreamEvent>& events) {
  std::vector<Kind> out;
  for (const StreamEvent& event : events) out.push_back(event.kind);
  return out;
}

std::vector<Telegram> telegrams(const std::vector<StreamEvent>& events) {
  std::vector<Telegram> out;
  for (const StreamEvent& event : events) {
    if (event.kind == Kind::kTelegram) out.push_back(event.telegram);
  }
  return out;
}

void expect_bytes_accounted(const TelegramStream& stream) {
  const StreamStats& s = stream.stats();
  EXPECT_EQ(s.bytes, s.telegram_bytes + s.acks + s.naks + s.discarded_bytes + stream.buffered());
}

// A measured-values telegram with `count` values 100, 101, ... in `units`.
MeasuredValues ramp(std::size_t count, MeasuringUnits units = MeasuringUnits::kCentimetres) {
  MeasuredValues values;
  values.units = units;
  values.status = 0x10;
  for (std::size_t i = 0; i < count; ++i)
    values.values.push_back(static_cast<std::uint16_t>(100 + i));
  return values;
}

// --- CRC ---------------------------------------------------------------------------------------

TEST(SickLms2xxCrc, MatchesTheCrcOfPublishedTelegrams) {
  // Requests as drivers in the field send them, CRC low byte first on the wire.
  EXPECT_EQ(crc16(Bytes{0x02, 0x00, 0x01, 0x00, 0x31}), 0x1215);        // status: .. 15 12
  EXPECT_EQ(crc16(Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x24}), 0x0834);  // continuous: .. 34 08
  EXPECT_EQ(crc16(Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x25}), 0x0835);  // stop: .. 35 08
  EXPECT_EQ(crc16(Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x48}), 0x0858);  // 500000: .. 58 08
  EXPECT_EQ(crc16(Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x40}), 0x0850);  // 38400: .. 50 08
  EXPECT_EQ(crc16(Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x42}), 0x0852);  // 9600: .. 52 08
  EXPECT_EQ(crc16(Bytes{0x02, 0x00, 0x05, 0x00, 0x3B, 0x64, 0x00, 0x64, 0x00}), 0x0F1D);
  EXPECT_EQ(crc16(Bytes{0x02, 0x00, 0x05, 0x00, 0x3B, 0xB4, 0x00, 0x32, 0x00}), 0x1F3B);
  EXPECT_EQ(crc16(Bytes{0x02, 0x00, 0x05, 0x00, 0x3B, 0x64, 0x00, 0x19, 0x00}), 0x72E7);
  // Installation mode with "SICK_LMS": .. BE C5.
  EXPECT_EQ(
      crc16(Bytes{0x02, 0x00, 0x0A, 0x00, 0x20, 0x00, 'S', 'I', 'C', 'K', '_', 'L', 'M', 'S'}),
      0xC5BE);
}

TEST(SickLms2xxCrc, MatchesTheCrcOfRepliesFromTheDevice) {
  // A mode-switch reply captured from an LMS at address 0: ACK, then 02 80 03 00 A0 00 10 16 0A.
  EXPECT_EQ(crc16(Bytes{0x02, 0x80, 0x03, 0x00, 0xA0, 0x00, 0x10}), 0x0A16);
  // The quick manual's examples from an LMS at address 1 (reply address 0x81).
  EXPECT_EQ(crc16(Bytes{0x02, 0x81, 0x03, 0x00, 0xA0, 0x00, 0x10}), 0x1A36);
  EXPECT_EQ(crc16(Bytes{0x02, 0x81, 0x07, 0x00, 0xBB, 0x01, 0x64, 0x00, 0x64, 0x00, 0x10}), 0x3F4A);
  EXPECT_EQ(crc16(Bytes{}), 0);
}

// --- Requests, byte for byte ---------------------------------------------------------------

TEST(SickLms2xxRequests, ModeSwitchesAreBuiltByteForByte) {
  // STX, address 0 (the LMS), length 2 (low, high), command 0x20, mode, CRC (low, high).
  EXPECT_EQ(mode_switch_request(OperatingMode::kContinuousAllValues),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x24, 0x34, 0x08}));
  EXPECT_EQ(mode_switch_request(OperatingMode::kOnRequest),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x25, 0x35, 0x08}));
  const Bytes partial = mode_switch_request(OperatingMode::kContinuousPartialScans);
  EXPECT_EQ(Bytes(partial.begin(), partial.end() - 2), (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x2A}));
  EXPECT_EQ(crc_field(partial), crc_of(partial));
  // Installation: length 10 = command, mode 0x00 and the 8-character password.
  const Bytes installation{0x02, 0x00, 0x0A, 0x00, 0x20, 0x00, 0x53, 0x49,
                           0x43, 0x4B, 0x5F, 0x4C, 0x4D, 0x53, 0xBE, 0xC5};
  EXPECT_EQ(mode_switch_request(OperatingMode::kInstallation), installation);
  EXPECT_EQ(installation_mode_request("SICK_LMS"), installation);
  const Bytes short_password = installation_mode_request("ABC");
  EXPECT_EQ(short_password.size(), installation.size());
  EXPECT_EQ(short_password[9], ' ') << "padded to 8 characters";
}

TEST(SickLms2xxRequests, BaudRateSwitchesAreBuiltByteForByte) {
  // The baud rates are mode bytes of command 0x20: 0x42 9600, 0x41 19200, 0x40 38400, 0x48 500k.
  EXPECT_EQ(baud_rate_request(BaudRate::k38400),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x40, 0x50, 0x08}));
  EXPECT_EQ(baud_rate_request(BaudRate::k500000),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x48, 0x58, 0x08}));
  EXPECT_EQ(baud_rate_request(BaudRate::k9600),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x42, 0x52, 0x08}));
  EXPECT_EQ(baud_rate_request(BaudRate::k19200),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x41, 0x51, 0x08}));
  EXPECT_EQ(bits_per_second(BaudRate::k500000), 500000);
  EXPECT_EQ(baud_rate_from_bps(38400), BaudRate::k38400);
  EXPECT_FALSE(baud_rate_from_bps(115200).has_value());
}

TEST(SickLms2xxRequests, VariantAndStatusRequestsAreBuiltByteForByte) {
  // Command 0x3B, angle (2 bytes, deg), resolution (2 bytes, 1/100 deg), all low byte first.
  EXPECT_EQ(variant_request({ScanAngle::k100Deg, AngularResolution::kOneDeg}),
            (Bytes{0x02, 0x00, 0x05, 0x00, 0x3B, 0x64, 0x00, 0x64, 0x00, 0x1D, 0x0F}));
  EXPECT_EQ(variant_request({ScanAngle::k180Deg, AngularResolution::kHalfDeg}),
            (Bytes{0x02, 0x00, 0x05, 0x00, 0x3B, 0xB4, 0x00, 0x32, 0x00, 0x3B, 0x1F}));
  EXPECT_EQ(variant_request({ScanAngle::k180Deg, AngularResolution::kOneDeg}),
            (Bytes{0x02, 0x00, 0x05, 0x00, 0x3B, 0xB4, 0x00, 0x64, 0x00, 0x97, 0x49}));
  EXPECT_EQ(variant_request({ScanAngle::k100Deg, AngularResolution::kQuarterDeg}),
            (Bytes{0x02, 0x00, 0x05, 0x00, 0x3B, 0x64, 0x00, 0x19, 0x00, 0xE7, 0x72}));
  // Command 0x31 alone.
  EXPECT_EQ(status_request(), (Bytes{0x02, 0x00, 0x01, 0x00, 0x31, 0x15, 0x12}));
}

TEST(SickLms2xxRequests, VariantsAndTheirScans) {
  EXPECT_FALSE(is_supported({ScanAngle::k180Deg, AngularResolution::kQuarterDeg}));
  EXPECT_TRUE(is_supported({ScanAngle::k100Deg, AngularResolution::kQuarterDeg}));
  EXPECT_EQ(values_per_scan({ScanAngle::k180Deg, AngularResolution::kOneDeg}), 181U);
  EXPECT_EQ(values_per_scan({ScanAngle::k180Deg, AngularResolution::kHalfDeg}), 361U);
  EXPECT_EQ(values_per_scan({ScanAngle::k100Deg, AngularResolution::kQuarterDeg}), 401U);
  EXPECT_EQ(rotations_per_scan(AngularResolution::kQuarterDeg), 4);
  EXPECT_FALSE(variant_from(90, 100).has_value());
  EXPECT_FALSE(variant_from(180, 10).has_value());
}

// --- Framing -----------------------------------------------------------------------------------

TEST(SickLms2xxTelegram, EncodesAndParsesOneTelegram) {
  const Bytes payload{0xA0, 0x00, 0x10};
  const Bytes bytes = encode_telegram(kReplyAddress, payload);
  EXPECT_EQ(bytes, (Bytes{0x02, 0x80, 0x03, 0x00, 0xA0, 0x00, 0x10, 0x16, 0x0A}));
  const std::optional<Telegram> telegram = parse_telegram(bytes);
  ASSERT_TRUE(telegram.has_value());
  EXPECT_EQ(telegram->address, 0x80);
  EXPECT_EQ(telegram->payload, payload);
  EXPECT_EQ(telegram->command(), 0xA0);
  EXPECT_EQ(telegram->status(), 0x10);

  Bytes bad_crc = bytes;
  bad_crc.back() ^= 0x01;
  EXPECT_FALSE(parse_telegram(bad_crc).has_value());
  Bytes swapped_crc = bytes;
  std::swap(swapped_crc[7], swapped_crc[8]);
  EXPECT_FALSE(parse_telegram(swapped_crc).has_value()) << "the CRC goes low byte first";
  EXPECT_FALSE(parse_telegram(Bytes(bytes.begin(), bytes.end() - 1)).has_value());
  Bytes no_stx = bytes;
  no_stx[0] = 0x03;
  EXPECT_FALSE(parse_telegram(no_stx).has_value());
  EXPECT_FALSE(parse_telegram(Bytes{}).has_value());
}

TEST(SickLms2xxTelegram, TransmissionTimeCountsTenBitsPerByte) {
  EXPECT_DOUBLE_EQ(transmission_time_s(372, 38400), 372 * 10.0 / 38400.0);
  EXPECT_DOUBLE_EQ(transmission_time_s(10, 0), 0.0);
}

// --- Stream parser -----------------------------------------------------------------------------

// ACK, the reply to a mode switch, ACK, a variant reply, a scan: what a start-up looks like.
Bytes start_up_stream() {
  return join({{kAckByte},
               mode_switch_reply({kModeSwitchAccepted, 0x10}),
               {kAckByte},
               variant_reply({true, 180, 100, 0x10}),
               measured_values_telegram(ramp(181))});
}

TEST(SickLms2xxStream, FindsTelegramsAndAcksInOneRead) {
  TelegramStream stream;
  const std::vector<StreamEvent> events = stream.feed(start_up_stream());
  EXPECT_EQ(kinds(events), (std::vector<Kind>{Kind::kAck, Kind::kTelegram, Kind::kAck,
                                              Kind::kTelegram, Kind::kTelegram}));
  EXPECT_EQ(parse_mode_switch_reply(events[1].telegram), (ModeSwitchReply{0x00, 0x10}));
  EXPECT_EQ(parse_variant_reply(events[3].telegram), (VariantReply{true, 180, 100, 0x10}));
  EXPECT_EQ(decode_measured_values(events[4].telegram), ramp(181));
  EXPECT_EQ(stream.stats().telegrams, 3U);
  EXPECT_EQ(stream.stats().acks, 2U);
  EXPECT_EQ(stream.stats().discarded_bytes, 0U);
  EXPECT_EQ(stream.buffered(), 0U);
  expect_bytes_accounted(stream);
}

TEST(SickLms2xxStream, OneByteAtATimeGivesTheSameEvents) {
  const Bytes bytes = start_up_stream();
  TelegramStream whole;
  const std::vector<StreamEvent> expected = whole.feed(bytes);
  TelegramStream stream;
  std::vector<StreamEvent> events;
  for (const std::uint8_t byte : bytes) {
    for (StreamEvent& event : stream.feed(Bytes{byte})) events.push_back(std::move(event));
    EXPECT_TRUE(stream.feed(Bytes{}).empty());
  }
  EXPECT_EQ(kinds(events), kinds(expected));
  EXPECT_EQ(telegrams(events), telegrams(expected));
}

TEST(SickLms2xxStream, RandomChunksGiveTheSameEvents) {
  Bytes bytes;
  for (int i = 0; i < 20; ++i) bytes = join({bytes, start_up_stream()});
  TelegramStream whole;
  const std::vector<StreamEvent> expected = whole.feed(bytes);
  ASSERT_EQ(telegrams(expected).size(), 60U);
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    TelegramStream stream;
    std::vector<StreamEvent> events;
    std::size_t at = 0;
    while (at < bytes.size()) {
      const std::size_t size = std::min<std::size_t>(bytes.size() - at, 1 + rng() % 900);
      for (StreamEvent& event : stream.feed(std::span(bytes).subspan(at, size))) {
        events.push_back(std::move(event));
      }
      at += size;
    }
    EXPECT_EQ(kinds(events), kinds(expected));
    EXPECT_EQ(telegrams(events), telegrams(expected));
    expect_bytes_accounted(stream);
  }
}

TEST(SickLms2xxStream, SkipsGarbageAndStrayStxBeforeAndBetweenTelegrams) {
  const Bytes reply = mode_switch_reply({kModeSwitchAccepted, 0x10});
  // Garbage with a lone STX, an STX followed by another address, and a false header 02 80 05 00
  // that claims five bytes of payload (its command byte 0x02 lacks the reply bit).
  const Bytes garbage{0x55, 0x02, 0xAA, 0x02, 0x00, 0x02, 0x80, 0x05, 0x00};
  TelegramStream stream;
  const std::vector<StreamEvent> events =
      stream.feed(join({garbage, reply, garbage, {kNakByte}, reply}));
  EXPECT_EQ(kinds(events), (std::vector<Kind>{Kind::kTelegram, Kind::kNak, Kind::kTelegram}));
  EXPECT_EQ(stream.stats().discarded_bytes, 2 * garbage.size());
  expect_bytes_accounted(stream);
}

TEST(SickLms2xxStream, AFalseHeaderWithAPlausibleLengthIsLeftAtItsCrc) {
  // 02 80 then a length of 3 and a reply-like command: the parser must wait for the "telegram",
  // fail its CRC, and find the real one that started inside it.
  const Bytes reply = mode_switch_reply({kModeSwitchAccepted, 0x10});
  const Bytes false_header{0x02, 0x80, 0x03, 0x00, 0xA0};
  TelegramStream stream;
  const std::vector<StreamEvent> events = stream.feed(join({false_header, reply}));
  EXPECT_EQ(kinds(events), (std::vector<Kind>{Kind::kBadCrc, Kind::kTelegram}));
  EXPECT_EQ(telegrams(events)[0].payload, (Bytes{0xA0, 0x00, 0x10}));
  EXPECT_EQ(stream.stats().crc_errors, 1U);
  EXPECT_EQ(stream.stats().discarded_bytes, false_header.size());
}

TEST(SickLms2xxStream, ABadCrcTelegramIsDroppedCountedAndTheNextOneParsed) {
  Bytes bad = measured_values_telegram(ramp(181));
  bad[100] ^= 0x40;  // a bit flipped on the line
  const Bytes good = measured_values_telegram(ramp(181));
  TelegramStream stream;
  const std::vector<StreamEvent> events = stream.feed(join({bad, good}));
  EXPECT_EQ(kinds(events), (std::vector<Kind>{Kind::kBadCrc, Kind::kTelegram}));
  EXPECT_EQ(decode_measured_values(events[1].telegram), ramp(181));
  EXPECT_EQ(stream.stats().crc_errors, 1U);
  EXPECT_EQ(stream.stats().telegrams, 1U);
  EXPECT_EQ(stream.stats().discarded_bytes, bad.size());
  expect_bytes_accounted(stream);
}

TEST(SickLms2xxStream, AckAndNakBytesInsideABadTelegramAreNotReported) {
  // Values whose bytes are 06 00 and 15 00, then a broken CRC.
  MeasuredValues values = ramp(181);
  values.values[0] = kAckByte;
  values.values[1] = kNakByte;
  Bytes bad = measured_values_telegram(values);
  bad.back() ^= 0x01;
  TelegramStream stream;
  const std::vector<StreamEvent> events = stream.feed(join({bad, {kAckByte}}));
  EXPECT_EQ(kinds(events), (std::vector<Kind>{Kind::kBadCrc, Kind::kAck}))
      << "only the ACK after the telegram";
}

TEST(SickLms2xxStream, ControlAndStxBytesInsideAGoodTelegramAreData) {
  MeasuredValues values = ramp(181);
  values.values[0] = 0x8002;  // 02 80: looks like a header inside the payload
  values.values[1] = kAckByte;
  values.values[2] = kNakByte;
  TelegramStream stream;
  const std::vector<StreamEvent> events = stream.feed(measured_values_telegram(values));
  ASSERT_EQ(kinds(events), (std::vector<Kind>{Kind::kTelegram}));
  EXPECT_EQ(decode_measured_values(events[0].telegram), values);
  EXPECT_EQ(stream.stats().acks + stream.stats().naks, 0U);
}

TEST(SickLms2xxStream, AScanWhoseLengthDisagreesWithItsCountIsNotWaitedFor) {
  // 02 80 D6 02 B0 (726 bytes) but a count of 181 (which needs 366): rejected at once.
  const Bytes reply = mode_switch_reply({kModeSwitchAccepted, 0x10});
  TelegramStream stream;
  const std::vector<StreamEvent> events =
      stream.feed(join({{0x02, 0x80, 0xD6, 0x02, 0xB0, 0xB5, 0x00}, reply}));
  EXPECT_EQ(kinds(events), (std::vector<Kind>{Kind::kTelegram}));
  EXPECT_EQ(stream.stats().crc_errors, 0U);
}

TEST(SickLms2xxStream, RequestsToTheLmsAreNotReplies) {
  // The host side ignores its own requests echoed back (address 0, command without reply bit).
  TelegramStream host;
  EXPECT_TRUE(telegrams(host.feed(status_request())).empty());
  // The device side finds them, and ignores the reply address.
  TelegramStream device(StreamDirection::kToLms);
  const std::vector<StreamEvent> events =
      device.feed(join({status_request(), mode_switch_reply({0, 0x10}), {kAckByte}}));
  ASSERT_EQ(kinds(events), (std::vector<Kind>{Kind::kTelegram}));
  EXPECT_EQ(events[0].telegram.payload, (Bytes{0x31}));
}

TEST(SickLms2xxStream, TheBufferStaysBoundedUnderEndlessGarbage) {
  TelegramStream stream;
  std::mt19937_64 rng(3);
  Bytes garbage(100000);
  for (std::uint8_t& byte : garbage) byte = static_cast<std::uint8_t>(rng());
  // Make it hostile: many plausible headers with long lengths.
  for (std::size_t i = 0; i + 6 < garbage.size(); i += 997) {
    garbage[i] = 0x02;
    garbage[i + 1] = 0x80;
    garbage[i + 2] = 0x90;
    garbage[i + 3] = 0x05;
    garbage[i + 4] = 0x92;
  }
  for (std::size_t at = 0; at < garbage.size(); at += 4096) {
    stream.feed(std::span(garbage).subspan(at, std::min<std::size_t>(4096, garbage.size() - at)));
    EXPECT_LE(stream.buffered(), TelegramStream::kCapacityBytes);
  }
  EXPECT_EQ(stream.stats().bytes, garbage.size());
  expect_bytes_accounted(stream);
  const std::vector<StreamEvent> events = stream.feed(join({Bytes(1500, 0x00), start_up_stream()}));
  EXPECT_EQ(telegrams(events).size(), 3U) << "back in sync after the garbage";
}

TEST(SickLms2xxStream, ResetForgetsAPartialTelegram) {
  const Bytes reply = mode_switch_reply({kModeSwitchAccepted, 0x10});
  TelegramStream stream;
  EXPECT_TRUE(stream.feed(Bytes(reply.begin(), reply.begin() + 5)).empty());
  EXPECT_EQ(stream.buffered(), 5U);
  stream.reset();
  EXPECT_EQ(stream.buffered(), 0U);
  EXPECT_EQ(telegrams(stream.feed(reply)).size(), 1U);
  expect_bytes_accounted(stream);
}

// --- Replies -----------------------------------------------------------------------------------

TEST(SickLms2xxReplies, ParsesACapturedModeSwitchReply) {
  TelegramStream stream;
  const std::vector<StreamEvent> events =
      stream.feed(Bytes{0x06, 0x02, 0x80, 0x03, 0x00, 0xA0, 0x00, 0x10, 0x16, 0x0A});
  ASSERT_EQ(kinds(events), (std::vector<Kind>{Kind::kAck, Kind::kTelegram}));
  const std::optional<ModeSwitchReply> reply = parse_mode_switch_reply(events[1].telegram);
  ASSERT_TRUE(reply.has_value());
  EXPECT_TRUE(reply->accepted());
  EXPECT_EQ(reply->status, 0x10);
  EXPECT_FALSE(parse_variant_reply(events[1].telegram).has_value());
  EXPECT_FALSE(parse_mode_switch_reply(Telegram{0x80, {0xA0, 0x00}}).has_value());
  EXPECT_FALSE(parse_mode_switch_reply(Telegram{0x80, {0xA0, 0x01, 0x10}})->accepted());
}

TEST(SickLms2xxReplies, ParsesTheQuickManualsVariantReply) {
  // From an LMS at address 1: accepted (01), 100 deg (64 00), 1 deg (64 00), status 10.
  const Bytes bytes{0x02, 0x81, 0x07, 0x00, 0xBB, 0x01, 0x64, 0x00, 0x64, 0x00, 0x10, 0x4A, 0x3F};
  const std::optional<Telegram> telegram = parse_telegram(bytes);
  ASSERT_TRUE(telegram.has_value());
  const std::optional<VariantReply> reply = parse_variant_reply(*telegram);
  ASSERT_TRUE(reply.has_value());
  EXPECT_TRUE(reply->accepted);
  EXPECT_EQ(reply->variant(), (Variant{ScanAngle::k100Deg, AngularResolution::kOneDeg}));
  EXPECT_EQ(variant_reply(*reply).size(), bytes.size());
  // A host stream for address 0 does not take address 1's telegrams, one for 0x81 does.
  EXPECT_TRUE(telegrams(TelegramStream().feed(bytes)).empty());
  EXPECT_EQ(telegrams(TelegramStream(StreamDirection::kFromLms, 0x81).feed(bytes)).size(), 1U);
}

TEST(SickLms2xxReplies, StatusReplyRoundTrips) {
  StatusReply status;
  status.software_version = "V02.10 ";
  status.operating_mode = 0x25;
  status.measuring_mode = 0x00;
  status.angle_deg = 180;
  status.resolution_cdeg = 50;
  status.baud_bps = 38400;
  status.units_code = 1;
  status.status = 0x10;
  const Bytes bytes = status_reply(status);
  // 02 80 9A 00 B1 ...: 154 bytes of payload, as LMS units send it.
  EXPECT_EQ(Bytes(bytes.begin(), bytes.begin() + 5), (Bytes{0x02, 0x80, 0x9A, 0x00, 0xB1}));
  EXPECT_EQ(bytes[4 + 116], 0x19) << "38400 baud: divider word 0x8019";
  EXPECT_EQ(bytes[4 + 117], 0x80);
  const std::optional<StatusReply> parsed = parse_status_reply(*parse_telegram(bytes));
  ASSERT_TRUE(parsed.has_value());
  EXPECT_EQ(*parsed, status);
  EXPECT_EQ(parsed->units(), MeasuringUnits::kMillimetres);
  EXPECT_FALSE(parse_status_reply(Telegram{0x80, {0xB1, 0x10}}).has_value());
}

// --- Measured values ---------------------------------------------------------------------------

TEST(SickLms2xxScan, DecodesTheCountWordUnitsAndFlags) {
  // 361 values in mm: count word 0x4169 (69 41 on the wire), as LMS units in mm mode send it.
  MeasuredValues mm = ramp(361, MeasuringUnits::kMillimetres);
  const Bytes bytes = measured_values_telegram(mm);
  EXPECT_EQ(Bytes(bytes.begin(), bytes.begin() + 7),
            (Bytes{0x02, 0x80, 0xD6, 0x02, 0xB0, 0x69, 0x41}));
  EXPECT_EQ(bytes.size(), 732U);
  EXPECT_EQ(decode_measured_values(*parse_telegram(bytes)), mm);

  // 181 values in cm: length 366 (6E 01), count word 0x00B5 (B5 00).
  const Bytes cm = measured_values_telegram(ramp(181));
  EXPECT_EQ(Bytes(cm.begin(), cm.begin() + 7), (Bytes{0x02, 0x80, 0x6E, 0x01, 0xB0, 0xB5, 0x00}));

  // Part 3 of an interlaced scan, 180 values: bit 13 (partial), bits 11-12 = 3 -> 0x38B4.
  MeasuredValues part = ramp(180);
  part.partial_scan = true;
  part.partial_index = 3;
  const Bytes part_bytes = measured_values_telegram(part);
  EXPECT_EQ(part_bytes[5], 0xB4);
  EXPECT_EQ(part_bytes[6], 0x38);
  const std::optional<MeasuredValues> decoded = decode_measured_values(*parse_telegram(part_bytes));
  ASSERT_TRUE(decoded.has_value());
  EXPECT_TRUE(decoded->partial_scan);
  EXPECT_EQ(decoded->partial_index, 3);
}

TEST(SickLms2xxScan, DecodesTheRealTimeIndex) {
  MeasuredValues values = ramp(101);
  values.real_time_index = 0x42;
  const std::optional<MeasuredValues> decoded =
      decode_measured_values(*parse_telegram(measured_values_telegram(values)));
  ASSERT_TRUE(decoded.has_value());
  EXPECT_EQ(decoded->real_time_index, 0x42);
  EXPECT_EQ(decoded->status, 0x10);
  // Two index bytes (as some documentation has it) are taken too.
  Bytes payload = parse_telegram(measured_values_telegram(ramp(101)))->payload;
  payload.insert(payload.end() - 1, {0x34, 0x12});
  EXPECT_EQ(decode_measured_values(Telegram{0x80, payload})->real_time_index, 0x1234);
}

TEST(SickLms2xxScan, RejectsMalformedMeasuredValues) {
  const Bytes good = parse_telegram(measured_values_telegram(ramp(181)))->payload;
  Bytes too_short = good;
  too_short.pop_back();
  too_short.pop_back();
  EXPECT_FALSE(decode_measured_values(Telegram{0x80, too_short}).has_value());
  Bytes too_long = good;
  too_long.insert(too_long.end(), {0, 0, 0});
  EXPECT_FALSE(decode_measured_values(Telegram{0x80, too_long}).has_value());
  Bytes decimetres = good;
  decimetres[2] |= 0x80;  // units 2
  EXPECT_FALSE(decode_measured_values(Telegram{0x80, decimetres}).has_value());
  Bytes not_b0 = good;
  not_b0[0] = 0xB6;
  EXPECT_FALSE(decode_measured_values(Telegram{0x80, not_b0}).has_value());
  // 1023 values claimed (more than 721).
  EXPECT_FALSE(decode_measured_values(Telegram{0x80, {0xB0, 0xFF, 0x03, 0x10}}).has_value());
  EXPECT_FALSE(decode_measured_values(Telegram{0x80, {}}).has_value());
}

TEST(SickLms2xxScan, RangeCodesAndFlagBits) {
  EXPECT_EQ(range_error_code(RangeError::kTooFar, 13), 8183);
  EXPECT_EQ(range_error_code(RangeError::kNotValid, 13), 8191);
  EXPECT_EQ(range_error_code(RangeError::kDazzled, 13), 8190);
  EXPECT_EQ(range_error_code(RangeError::kOverflow, 13), 8189);
  EXPECT_EQ(range_error_code(RangeError::kLowSignal, 13), 8187);
  EXPECT_EQ(range_error_code(RangeError::kChannelError, 13), 8186);
  EXPECT_EQ(range_error_code(RangeError::kTooFar, 15), 32759);
  EXPECT_EQ(max_range_code(13), 8182);
  // Field A flag (bit 13) on a 1234 range in the 13-bit modes.
  EXPECT_EQ(range_code(0x2000 | 1234, 13), 1234);
  EXPECT_EQ(flag_bits(0x2000 | 1234, 13), 0x2000);
  EXPECT_EQ(range_code(0x2000 | 1234, 15), 0x2000 | 1234);
  EXPECT_EQ(range_bits_for_measuring_mode(0x00), 13);
  EXPECT_EQ(range_bits_for_measuring_mode(0x04), 14);
  EXPECT_EQ(range_bits_for_measuring_mode(0x06), 15);
  EXPECT_EQ(range_bits_for_measuring_mode(0x0F), 16);
  EXPECT_EQ(range_bits_for_measuring_mode(0x3F), 0);
}

// --- Conversion --------------------------------------------------------------------------------

TEST(SickLms2xxScan, OneDegreeScanCoversMinusToPlusNinetyCounterClockwise) {
  MeasuredValues values = ramp(181);
  LaserScanOptions options;
  options.stamp_s = 12.5;
  const std::optional<msgs::LaserScan> scan = to_laser_scan(values, options);
  ASSERT_TRUE(scan.has_value());
  EXPECT_DOUBLE_EQ(scan->stamp_s, 12.5);
  EXPECT_NEAR(scan->angle_min_rad, -std::numbers::pi / 2, 1e-6) << "beam 0 on the right";
  EXPECT_NEAR(scan->angle_increment_rad, 1.0 * kDeg, 1e-7);
  ASSERT_EQ(scan->ranges_m.size(), 181U);
  EXPECT_NEAR(scan->angle_min_rad + 180 * scan->angle_increment_rad, std::numbers::pi / 2, 1e-5);
  EXPECT_NEAR(scan->ranges_m[0], 1.00, 1e-6) << "100 cm";
  EXPECT_NEAR(scan->ranges_m[180], 2.80, 1e-6);
  EXPECT_FLOAT_EQ(scan->range_min_m, 0.4F);
  EXPECT_FLOAT_EQ(scan->range_max_m, 80.0F);
  EXPECT_EQ(scan->sensor_in_base, (geometry::Pose2D{0.2, 0.0, 0.0}));
}

TEST(SickLms2xxScan, AnglesFollowTheValueCount) {
  struct Case {
    std::size_t count;
    double first_deg;
    double step_deg;
  };
  for (const Case c : {Case{361, -90.0, 0.5}, Case{721, -90.0, 0.25}, Case{101, -50.0, 1.0},
                       Case{201, -50.0, 0.5}, Case{401, -50.0, 0.25}}) {
    const std::optional<msgs::LaserScan> scan = to_laser_scan(ramp(c.count), {});
    ASSERT_TRUE(scan.has_value()) << c.count;
    EXPECT_NEAR(scan->angle_min_rad, c.first_deg * kDeg, 1e-6) << c.count;
    EXPECT_NEAR(scan->angle_increment_rad, c.step_deg * kDeg, 1e-7) << c.count;
  }
  EXPECT_FALSE(to_laser_scan(ramp(180), {}).has_value()) << "no variant has 180 values";
  LaserScanOptions bad_bits;
  bad_bits.range_bits = 0;
  EXPECT_FALSE(to_laser_scan(ramp(181), bad_bits).has_value());
}

TEST(SickLms2xxScan, AnInterlacedPartStartsAtItsOffset) {
  MeasuredValues part = ramp(180);
  part.partial_scan = true;
  part.partial_index = 2;
  const std::optional<msgs::LaserScan> scan = to_laser_scan(part, {});
  ASSERT_TRUE(scan.has_value());
  EXPECT_NEAR(scan->angle_min_rad, -89.5 * kDeg, 1e-6);
  EXPECT_NEAR(scan->angle_increment_rad, 1.0 * kDeg, 1e-7);
  part.partial_index = 0;
  EXPECT_FALSE(to_laser_scan(part, {}).has_value()) << "part 0 has 181 values";
}

TEST(SickLms2xxScan, UnitsAndErrorCodesBecomeRangesOrNoReturn) {
  MeasuredValues values = ramp(181, MeasuringUnits::kMillimetres);
  values.values[0] = 2251;
  values.values[1] = range_error_code(RangeError::kTooFar, 13);
  values.values[2] = range_error_code(RangeError::kDazzled, 13);
  values.values[3] = range_error_code(RangeError::kNotValid, 13);
  values.values[4] = 0x4000 | 1500;  // field B flag on 1.5 m
  values.values[5] = 0;
  const std::optional<msgs::LaserScan> scan = to_laser_scan(values, {});
  ASSERT_TRUE(scan.has_value());
  // 13 bits of mm reach 8.182 m: the range maximum says so.
  EXPECT_NEAR(scan->range_max_m, 8.182, 1e-5);
  EXPECT_NEAR(scan->ranges_m[0], 2.251, 1e-6);
  for (int i = 1; i <= 3; ++i) {
    EXPECT_GT(scan->ranges_m[i], scan->range_max_m) << "no return at " << i;
  }
  EXPECT_NEAR(scan->ranges_m[4], 1.5, 1e-6);
  EXPECT_LT(scan->ranges_m[5], scan->range_min_m) << "0: nothing measured";

  // Read with the 32 m modes' 15 bits, 8183 is a range.
  LaserScanOptions wide;
  wide.range_bits = 15;
  EXPECT_NEAR(to_laser_scan(values, wide)->ranges_m[1], 8.183, 1e-6);

  // Centimetres: 80 m is in reach; 8182 cm is above the 80 m range maximum, so no return too.
  MeasuredValues cm = ramp(181);
  cm.values[0] = 7999;
  cm.values[1] = 8182;
  const std::optional<msgs::LaserScan> cm_scan = to_laser_scan(cm, {});
  EXPECT_NEAR(cm_scan->ranges_m[0], 79.99, 1e-4);
  EXPECT_FLOAT_EQ(cm_scan->range_max_m, 80.0F);
  EXPECT_GT(cm_scan->ranges_m[1], cm_scan->range_max_m);
}

// --- Interlacing -------------------------------------------------------------------------------

// Part `index` of an interlaced 180 deg scan whose value at 0.25 deg slot s is 1000 + s.
MeasuredValues part_of_quarter_scan(int index, std::size_t parts = 4) {
  MeasuredValues part;
  part.partial_scan = true;
  part.partial_index = index;
  part.status = 0x10;
  const std::size_t count = index == 0 ? 181 : 180;
  const std::size_t step = 4 / parts;
  for (std::size_t j = 0; j < count; ++j) {
    part.values.push_back(
        static_cast<std::uint16_t>(1000 + j * 4 + static_cast<std::size_t>(index) / step * step));
  }
  return part;
}

TEST(SickLms2xxInterlace, AssemblesAQuarterDegreeScanFromFourParts) {
  InterlacedScanAssembler assembler(AngularResolution::kQuarterDeg);
  for (int k = 0; k < 3; ++k) EXPECT_FALSE(assembler.add(part_of_quarter_scan(k)).has_value());
  const std::optional<MeasuredValues> scan = assembler.add(part_of_quarter_scan(3));
  ASSERT_TRUE(scan.has_value());
  ASSERT_EQ(scan->values.size(), 721U);
  EXPECT_FALSE(scan->partial_scan);
  for (std::size_t s = 0; s < 721; ++s) ASSERT_EQ(scan->values[s], 1000 + s) << s;
  const std::optional<msgs::LaserScan> laser = to_laser_scan(*scan, {});
  ASSERT_TRUE(laser.has_value());
  EXPECT_NEAR(laser->angle_min_rad, -std::numbers::pi / 2, 1e-6);
  EXPECT_NEAR(laser->angle_increment_rad, 0.25 * kDeg, 1e-7);
  // The next scan needs four new parts.
  EXPECT_FALSE(assembler.add(part_of_quarter_scan(0)).has_value());
}

TEST(SickLms2xxInterlace, PartsMayComeInAnyOrderButNotStale) {
  InterlacedScanAssembler assembler(AngularResolution::kQuarterDeg);
  // A slow line: the LMS sent the parts of rotations 0, 7, 14, 21 (indices 0, 3, 2, 1).
  EXPECT_FALSE(assembler.add(part_of_quarter_scan(0)).has_value());
  EXPECT_FALSE(assembler.add(part_of_quarter_scan(3)).has_value());
  EXPECT_FALSE(assembler.add(part_of_quarter_scan(2)).has_value());
  EXPECT_TRUE(assembler.add(part_of_quarter_scan(1)).has_value());
  // Every 8th rotation: always part 0 — never a complete scan.
  for (int i = 0; i < 10; ++i) EXPECT_FALSE(assembler.add(part_of_quarter_scan(0)).has_value());
  // A part 0 that is four parts old does not join the ones after it.
  assembler.reset();
  EXPECT_FALSE(assembler.add(part_of_quarter_scan(0)).has_value());
  EXPECT_FALSE(assembler.add(part_of_quarter_scan(1)).has_value());
  EXPECT_FALSE(assembler.add(part_of_quarter_scan(1)).has_value());
  EXPECT_FALSE(assembler.add(part_of_quarter_scan(2)).has_value());
  EXPECT_FALSE(assembler.add(part_of_quarter_scan(3)).has_value()) << "part 0 is four parts old";
  EXPECT_TRUE(assembler.add(part_of_quarter_scan(0)).has_value());
}

TEST(SickLms2xxInterlace, AssemblesAHalfDegreeScanFromPartsZeroAndTwo) {
  InterlacedScanAssembler assembler(AngularResolution::kHalfDeg);
  EXPECT_FALSE(assembler.add(part_of_quarter_scan(1, 2)).has_value()) << "no part at 0.5 deg";
  EXPECT_FALSE(assembler.add(part_of_quarter_scan(0, 2)).has_value());
  const std::optional<MeasuredValues> scan = assembler.add(part_of_quarter_scan(2, 2));
  ASSERT_TRUE(scan.has_value());
  ASSERT_EQ(scan->values.size(), 361U);
  for (std::size_t s = 0; s < 361; ++s) ASSERT_EQ(scan->values[s], 1000 + 2 * s) << s;
}

TEST(SickLms2xxInterlace, CompleteScansPassThroughAndMismatchedPartsAreDropped) {
  InterlacedScanAssembler assembler(AngularResolution::kQuarterDeg);
  EXPECT_EQ(assembler.add(ramp(361)), ramp(361));
  MeasuredValues wrong_count = part_of_quarter_scan(1);
  wrong_count.values.pop_back();
  EXPECT_FALSE(assembler.add(wrong_count).has_value());
  // A change of units in between starts over.
  for (int k = 0; k < 3; ++k) assembler.add(part_of_quarter_scan(k));
  MeasuredValues mm = part_of_quarter_scan(3);
  mm.units = MeasuringUnits::kMillimetres;
  EXPECT_FALSE(assembler.add(mm).has_value());
}

}  // namespace
}  // namespace mobot::protocol::sick
