#include "drivers/protocol/ydlidar_g4.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <random>
#include <span>
#include <variant>
#include <vector>

#include "drivers/protocol/ydlidar_scan.h"
#include "drivers/protocol/ydlidar_stream_parser.h"

namespace mobot::protocol::ydlidar {
namespace {

using Bytes = std::vector<std::uint8_t>;

// The zero packet of the vendor's protocol document, byte for byte.
const Bytes kZeroPacket = {
    0xAA, 0x55,  // PH
    0x01,        // CT: bit 0, a new turn starts; no frequency in the upper bits
    0x01,        // LSN: one sample
    0x53, 0xAE,  // FSA 0xAE53: (0xAE53 >> 1) / 64 = 348.640625 deg
    0x53, 0xAE,  // LSA, the same
    0xAB, 0x54,  // CS 0x54AB = 0x55AA ^ 0xAE53 ^ 0x0000 ^ 0x0101 ^ 0xAE53
    0x00, 0x00,  // S1: distance 0, no return
};

// A point-cloud packet of three samples, worked out by hand.
const Bytes kCloudPacket = {
    0xAA, 0x55,  // PH
    0x00,        // CT: an ordinary packet
    0x03,        // LSN: three samples
    0x01, 0x05,  // FSA 0x0501: 10 deg * 64 = 640, << 1 | 1 = 1281
    0x01, 0x06,  // LSA 0x0601: 12 deg * 64 = 768, << 1 | 1 = 1537
    0x4A, 0x45,  // CS 0x454A = 0x55AA ^ 0x0501 ^ 0x0FA0 ^ 0x0000 ^ 0x1F40 ^ 0x0300 ^ 0x0601
    0xA0, 0x0F,  // S1 0x0FA0 = 4000: 1000 mm, at 10 deg
    0x00, 0x00,  // S2 0: no return, at 11 deg
    0x40, 0x1F,  // S3 0x1F40 = 8000: 2000 mm, at 12 deg
};

// The same layout with intensity: each sample is I, then Si.
const Bytes kIntensityPacket = {
    0xAA, 0x55,        // PH
    0x00,              // CT
    0x02,              // LSN: two samples
    0x01, 0x0A,        // FSA 0x0A01: 20 deg
    0x81, 0x0A,        // LSA 0x0A81: 21 deg
    0xF0, 0x37,        // CS 0x37F0 = 0x55AA ^ 0x0A01 ^ 0x001F ^ 0x6FE5 ^ 0x0080 ^ 0x0FA0 ^ 0x0200
                       //              ^ 0x0A81
    0x1F, 0xE5, 0x6F,  // I 0x1F, Si 0x6FE5: the document's example, 7161 mm, intensity 287
    0x80, 0xA0, 0x0F,  // I 0x80, Si 0x0FA0: 1000 mm
};

// Device info as the G4 sends it: model 5, firmware 1.2, hardware 1, serial 2020061500020007.
const Bytes kDeviceInfoResponse = {
    0xA5, 0x5A,              // response sync
    0x14, 0x00, 0x00, 0x00,  // length 20, mode 0 (single)
    0x04,                    // type: device info
    0x05,                    // model: G4
    0x02, 0x01,              // firmware 0x0102: major 1 (high byte), minor 2
    0x01,                    // hardware 1
    0x02, 0x00, 0x02, 0x00, 0x00, 0x06, 0x01, 0x05,
    0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x07,  // serial, one digit a byte
};

const Bytes kHealthResponse = {
    0xA5, 0x5A,              // response sync
    0x03, 0x00, 0x00, 0x00,  // length 3, single
    0x06,                    // type: health
    0x02,                    // status: error
    0x34, 0x12,              // error code 0x1234
};

// The answer to start scan: length 5 (meaningless), mode 1 in the top bits of 0x40, type 0x81.
const Bytes kStartScanResponse = {0xA5, 0x5A, 0x05, 0x00, 0x00, 0x40, 0x81};

Bytes concat(std::initializer_list<const Bytes*> parts) {
  Bytes out;
  for (const Bytes* part : parts) out.insert(out.end(), part->begin(), part->end());
  return out;
}

std::vector<StreamItem> parse_all(const Bytes& bytes, StreamParser& parser) {
  std::vector<StreamItem> items;
  parser.feed(bytes, items);
  return items;
}

std::size_t item_bytes(const StreamItem& item, SampleFormat format) {
  if (const auto* response = std::get_if<Response>(&item)) {
    return kResponseHeaderBytes + response->payload.size();
  }
  return kScanHeaderBytes + std::get<ScanPacket>(item).samples.size() * sample_bytes(format);
}

// Every byte fed is in a yielded item, discarded, or waiting in the buffer.
void expect_bytes_accounted(const StreamParser& parser, const std::vector<StreamItem>& items,
                            SampleFormat format = SampleFormat::kDistance) {
  std::uint64_t in_items = 0;
  for (const StreamItem& item : items) in_items += item_bytes(item, format);
  EXPECT_EQ(parser.stats().bytes,
            in_items + parser.stats().discarded_bytes + parser.buffered_bytes());
}

TEST(YdlidarG4Codec, CommandsAreA5ThenTheCode) {
  EXPECT_EQ(encode_command(Command::kStartScan), (std::array<std::uint8_t, 2>{0xA5, 0x60}));
  EXPECT_EQ(encode_command(Command::kStopScan), (std::array<std::uint8_t, 2>{0xA5, 0x65}));
  EXPECT_EQ(encode_command(Command::kGetDeviceInfo), (std::array<std::uint8_t, 2>{0xA5, 0x90}));
  EXPECT_EQ(encode_command(Command::kGetHealth), (std::array<std::uint8_t, 2>{0xA5, 0x92}));
  EXPECT_EQ(encode_command(Command::kRestart), (std::array<std::uint8_t, 2>{0xA5, 0x40}));
  EXPECT_EQ(encode_command(Command::kForceStop), (std::array<std::uint8_t, 2>{0xA5, 0x00}));
}

TEST(YdlidarG4Codec, ResponseHeaderSplitsLengthAndMode) {
  const auto start = decode_response_header(kStartScanResponse);
  ASSERT_TRUE(start.has_value());
  EXPECT_EQ(start->length, 5U);
  EXPECT_EQ(start->mode, ResponseMode::kContinuous);
  EXPECT_EQ(start->type, kTypeScan);
  EXPECT_TRUE(is_known_response(*start));

  const auto info = decode_response_header(kDeviceInfoResponse);
  ASSERT_TRUE(info.has_value());
  EXPECT_EQ(*info, (ResponseHeader{20, ResponseMode::kSingle, kTypeDeviceInfo}));

  // The top six bits of the fourth length byte belong to the length, the two above to the mode.
  const Bytes long_single = {0xA5, 0x5A, 0x01, 0x02, 0x03, 0x3F, 0x04};
  EXPECT_EQ(decode_response_header(long_single)->length, 0x3F030201U);
  EXPECT_FALSE(is_known_response(*decode_response_header(long_single)));
  const Bytes mode_two = {0xA5, 0x5A, 0x03, 0x00, 0x00, 0x80, 0x06};
  EXPECT_FALSE(decode_response_header(mode_two).has_value());

  for (const ResponseHeader& header :
       {*start, *info, ResponseHeader{0x3FFFFFFF, ResponseMode::kSingle, 0x06}}) {
    const auto bytes = encode_response_header(header);
    EXPECT_EQ(decode_response_header(bytes), header);
  }
  const auto start_bytes = encode_response_header(*start);
  EXPECT_EQ(Bytes(start_bytes.begin(), start_bytes.end()), kStartScanResponse);
}

TEST(YdlidarG4Codec, DeviceInfoAndHealthPayloads) {
  const std::span<const std::uint8_t> info_payload =
      std::span(kDeviceInfoResponse).subspan(kResponseHeaderBytes);
  const auto info = decode_device_info(info_payload);
  ASSERT_TRUE(info.has_value());
  EXPECT_EQ(info->model, kG4ModelCode);
  EXPECT_EQ(info->firmware_major, 1);
  EXPECT_EQ(info->firmware_minor, 2);
  EXPECT_EQ(info->hardware, 1);
  EXPECT_EQ(serial_number_text(*info), "2020061500020007");
  const auto encoded = encode_device_info(*info);
  EXPECT_TRUE(std::equal(encoded.begin(), encoded.end(), info_payload.begin()));
  EXPECT_FALSE(decode_device_info(info_payload.first(19)).has_value());

  const auto health = decode_health(std::span(kHealthResponse).subspan(kResponseHeaderBytes));
  ASSERT_TRUE(health.has_value());
  EXPECT_EQ(health->status, 2);
  EXPECT_EQ(health->error_code, 0x1234);
  EXPECT_EQ(encode_health(*health), (std::array<std::uint8_t, 3>{0x02, 0x34, 0x12}));
  EXPECT_FALSE(decode_health(Bytes{0x00, 0x00}).has_value());

  // 7.00 Hz in hundredths: 700 = 0x02BC.
  EXPECT_DOUBLE_EQ(*decode_scan_frequency_hz(Bytes{0xBC, 0x02, 0x00, 0x00}), 7.0);
  EXPECT_EQ(*decode_sampling_rate_hz(Bytes{0x02}), 9000);
  EXPECT_EQ(*decode_sampling_rate_hz(Bytes{0x00}), 4000);
  EXPECT_FALSE(decode_sampling_rate_hz(Bytes{0x07}).has_value());
}

TEST(YdlidarG4Codec, ChecksumIsTheXorOfTheWordsTheSdkReads) {
  EXPECT_EQ(scan_checksum(kZeroPacket, SampleFormat::kDistance), 0x54AB);
  EXPECT_EQ(scan_checksum(kCloudPacket, SampleFormat::kDistance), 0x454A);
  EXPECT_EQ(scan_checksum(kIntensityPacket, SampleFormat::kIntensity8), 0x37F0);
  EXPECT_EQ(scan_checksum(kIntensityPacket, SampleFormat::kIntensity10), 0x37F0);
  // Shorter than its LSN says.
  EXPECT_EQ(scan_checksum(std::span(kCloudPacket).first(13), SampleFormat::kDistance), 0);

  const std::vector<RawSample> samples = {{0x0FA0, 0}, {0x0000, 0}, {0x1F40, 0}};
  EXPECT_EQ(encode_scan_packet(0x00, 0x0501, 0x0601, samples, SampleFormat::kDistance),
            kCloudPacket);
  const std::vector<RawSample> intensity = {{0x6FE5, 0x1F}, {0x0FA0, 0x80}};
  EXPECT_EQ(encode_scan_packet(0x00, 0x0A01, 0x0A81, intensity, SampleFormat::kIntensity8),
            kIntensityPacket);
  const Bytes spoiled =
      encode_scan_packet(0x00, 0x0501, 0x0601, samples, SampleFormat::kDistance, 0xFFFF);
  EXPECT_EQ(spoiled[8], 0xB5);
  EXPECT_EQ(spoiled[9], 0xBA);
  EXPECT_TRUE(encode_scan_packet(0x00, 0x0501, 0x0601, {}, SampleFormat::kDistance).empty());
}

TEST(YdlidarG4Codec, AnglesAndTheirCorrection) {
  EXPECT_DOUBLE_EQ(angle_deg_from_raw(0xAE53), 348.640625);
  // The manual's example: FSA 0x6FE5 -> 223.78 deg, LSA 0x79BD -> 243.47 deg.
  EXPECT_NEAR(angle_deg_from_raw(0x6FE5), 223.78, 0.005);
  EXPECT_NEAR(angle_deg_from_raw(0x79BD), 243.47, 0.005);
  EXPECT_EQ(angle_raw_from_deg(10.0), 0x0501);
  EXPECT_EQ(angle_raw_from_deg(360.0), 0x0001);
  EXPECT_EQ(angle_raw_from_deg(-1.0), angle_raw_from_deg(359.0));

  // The manual's worked example: 1000 mm -> -6.7622 deg, 8000 mm -> -7.8374 deg.
  EXPECT_NEAR(angle_correction_deg(1000.0), -6.7622, 1e-4);
  EXPECT_NEAR(angle_correction_deg(8000.0), -7.8374, 1e-4);
  EXPECT_NEAR(angle_correction_deg(155.3), 0.0, 1e-12);
  EXPECT_EQ(angle_correction_deg(0.0), 0.0);  // no return, no correction

  // Si = 0x6FE5 is 7161.25 mm plain, 7161 mm when its low bits are the intensity's.
  EXPECT_DOUBLE_EQ(distance_mm_from_raw(0x6FE5, SampleFormat::kDistance), 7161.25);
  EXPECT_DOUBLE_EQ(distance_mm_from_raw(0x6FE5, SampleFormat::kIntensity8), 7161.0);
}

TEST(YdlidarG4Codec, DecodesThePacketsByHand) {
  const auto zero = decode_scan_packet(kZeroPacket, SampleFormat::kDistance);
  ASSERT_TRUE(zero.has_value());
  EXPECT_TRUE(zero->starts_scan());
  EXPECT_FALSE(zero->scan_frequency_hz().has_value());
  ASSERT_EQ(zero->samples.size(), 1U);
  EXPECT_DOUBLE_EQ(zero->samples[0].angle_deg, 348.640625);
  EXPECT_EQ(zero->samples[0].range_m, 0.0);

  const auto cloud = decode_scan_packet(kCloudPacket, SampleFormat::kDistance);
  ASSERT_TRUE(cloud.has_value());
  EXPECT_FALSE(cloud->starts_scan());
  EXPECT_EQ(cloud->checksum, 0x454A);
  ASSERT_EQ(cloud->samples.size(), 3U);
  // 10 deg - 6.762186 deg (1000 mm), 11 deg uncorrected (no return), 12 deg - 7.377244 (2000 mm).
  EXPECT_NEAR(cloud->samples[0].angle_deg, 3.237814, 1e-6);
  EXPECT_DOUBLE_EQ(cloud->samples[0].range_m, 1.0);
  EXPECT_DOUBLE_EQ(cloud->samples[1].angle_deg, 11.0);
  EXPECT_EQ(cloud->samples[1].range_m, 0.0);
  EXPECT_NEAR(cloud->samples[2].angle_deg, 4.622756, 1e-6);
  EXPECT_DOUBLE_EQ(cloud->samples[2].range_m, 2.0);

  EXPECT_FALSE(decode_scan_packet(std::span(kCloudPacket).first(15), SampleFormat::kDistance));
}

TEST(YdlidarG4Codec, InterpolationWrapsAt360AndSoDoesTheCorrection) {
  // FSA 359 deg, LSA 1 deg: the packet crosses zero, the three samples are 1 deg apart.
  const std::vector<RawSample> far = {{0, 0}, {0, 0}, {0, 0}};
  const auto crossing =
      decode_scan_packet(encode_scan_packet(0x00, 0xB381, 0x0081, far, SampleFormat::kDistance),
                         SampleFormat::kDistance);
  ASSERT_TRUE(crossing.has_value());
  EXPECT_DOUBLE_EQ(crossing->samples[0].angle_deg, 359.0);
  EXPECT_DOUBLE_EQ(crossing->samples[1].angle_deg, 0.0);
  EXPECT_DOUBLE_EQ(crossing->samples[2].angle_deg, 1.0);

  // A 1000 mm return at 2 deg is corrected to 2 - 6.762186 = -4.762186, i.e. 355.237814 deg.
  const std::vector<RawSample> near = {{4000, 0}};
  const auto below_zero =
      decode_scan_packet(encode_scan_packet(0x00, angle_raw_from_deg(2.0), angle_raw_from_deg(2.0),
                                            near, SampleFormat::kDistance),
                         SampleFormat::kDistance);
  ASSERT_TRUE(below_zero.has_value());
  EXPECT_NEAR(below_zero->samples[0].angle_deg, 355.237814, 1e-6);
}

TEST(YdlidarG4Codec, IntensityVariants) {
  const auto eight = decode_scan_packet(kIntensityPacket, SampleFormat::kIntensity8);
  ASSERT_TRUE(eight.has_value());
  ASSERT_EQ(eight->samples.size(), 2U);
  EXPECT_EQ(eight->samples[0].intensity, 0x1F);
  EXPECT_DOUBLE_EQ(eight->samples[0].range_m, 7.161);
  EXPECT_NEAR(eight->samples[0].angle_deg, 20.0 + angle_correction_deg(7161.0), 1e-9);
  EXPECT_EQ(eight->samples[1].intensity, 0x80);
  EXPECT_DOUBLE_EQ(eight->samples[1].range_m, 1.0);
  EXPECT_NEAR(eight->samples[1].angle_deg, 14.237814, 1e-6);

  // The 10-bit reading takes Si's low bits as intensity bits 8-9: (0xE5 & 3) << 8 | 0x1F = 287.
  const auto ten = decode_scan_packet(kIntensityPacket, SampleFormat::kIntensity10);
  ASSERT_TRUE(ten.has_value());
  EXPECT_EQ(ten->samples[0].intensity, 287);
  EXPECT_DOUBLE_EQ(ten->samples[0].range_m, 7.161);

  // The intensity packet read as plain samples has the wrong length.
  EXPECT_FALSE(decode_scan_packet(kIntensityPacket, SampleFormat::kDistance).has_value());

  StreamParser intensity_parser({SampleFormat::kIntensity8});
  const auto items = parse_all(concat({&kIntensityPacket, &kIntensityPacket}), intensity_parser);
  EXPECT_EQ(items.size(), 2U);
  EXPECT_EQ(intensity_parser.stats().checksum_errors, 0U);
  expect_bytes_accounted(intensity_parser, items, SampleFormat::kIntensity8);

  // A parser that expects plain samples finds no good packet in them.
  StreamParser plain_parser;
  EXPECT_TRUE(parse_all(concat({&kIntensityPacket, &kIntensityPacket}), plain_parser).empty());
  EXPECT_EQ(plain_parser.stats().scan_packets, 0U);
}

TEST(YdlidarG4Codec, ScanFrequencyRidesOnTheZeroPacket) {
  ScanPacket packet;
  packet.ct = 0x01 | 70 << 1;  // 7.0 Hz
  EXPECT_DOUBLE_EQ(*packet.scan_frequency_hz(), 7.0);
  packet.ct = 70 << 1;  // not a zero packet: the upper bits are something else
  EXPECT_FALSE(packet.scan_frequency_hz().has_value());
}

// A stream as the G4 sends it after A5 60: the answer, then packets.
Bytes scan_stream() {
  return concat({&kStartScanResponse, &kZeroPacket, &kCloudPacket, &kCloudPacket, &kZeroPacket,
                 &kCloudPacket});
}

void expect_scan_stream_items(const std::vector<StreamItem>& items) {
  ASSERT_EQ(items.size(), 6U);
  const auto* response = std::get_if<Response>(&items[0]);
  ASSERT_NE(response, nullptr);
  EXPECT_EQ(response->header.mode, ResponseMode::kContinuous);
  EXPECT_TRUE(response->payload.empty());
  for (std::size_t i = 1; i < items.size(); ++i) {
    const auto* packet = std::get_if<ScanPacket>(&items[i]);
    ASSERT_NE(packet, nullptr) << i;
    EXPECT_EQ(packet->starts_scan(), i == 1 || i == 4) << i;
  }
}

TEST(YdlidarG4StreamParser, ParsesAWholeStream) {
  StreamParser parser;
  const auto items = parse_all(scan_stream(), parser);
  expect_scan_stream_items(items);
  EXPECT_EQ(parser.stats().scan_packets, 5U);
  EXPECT_EQ(parser.stats().responses, 1U);
  EXPECT_EQ(parser.stats().discarded_bytes, 0U);
  EXPECT_EQ(parser.buffered_bytes(), 0U);
  expect_bytes_accounted(parser, items);
}

TEST(YdlidarG4StreamParser, OneByteAtATime) {
  StreamParser parser;
  std::vector<StreamItem> items;
  for (const std::uint8_t byte : scan_stream()) parser.feed(std::span(&byte, 1), items);
  expect_scan_stream_items(items);
  EXPECT_EQ(parser.stats().discarded_bytes, 0U);
  expect_bytes_accounted(parser, items);
}

TEST(YdlidarG4StreamParser, RandomChunks) {
  const Bytes stream = scan_stream();
  std::mt19937_64 rng(42);
  for (int trial = 0; trial < 200; ++trial) {
    StreamParser parser;
    std::vector<StreamItem> items;
    std::size_t at = 0;
    while (at < stream.size()) {
      const std::size_t size = std::min<std::size_t>(
          std::uniform_int_distribution<std::size_t>(0, 17)(rng), stream.size() - at);
      parser.feed(std::span(stream).subspan(at, size), items);
      at += size;
    }
    expect_scan_stream_items(items);
    EXPECT_EQ(parser.stats().discarded_bytes, 0U);
  }
}

TEST(YdlidarG4StreamParser, ResyncsAfterGarbage) {
  // Noise with lone sync bytes and half headers in it: AA not followed by 55, A5 not by 5A, and an
  // A5 5A header of a type the G4 never sends.
  const Bytes garbage = {0x00, 0x13, 0xAA, 0x00, 0xA5, 0x11, 0xFF, 0x55, 0xAA,
                         0xA5, 0x5A, 0x02, 0x00, 0x00, 0x00, 0x07, 0x5A};
  const Bytes stream =
      concat({&garbage, &kStartScanResponse, &garbage, &kZeroPacket, &garbage, &kCloudPacket,
              &kCloudPacket, &garbage, &kZeroPacket, &kCloudPacket, &garbage});
  StreamParser parser;
  std::vector<StreamItem> items;
  for (std::size_t at = 0; at < stream.size(); at += 5) {
    parser.feed(std::span(stream).subspan(at, std::min<std::size_t>(5, stream.size() - at)), items);
  }
  expect_scan_stream_items(items);
  EXPECT_EQ(parser.stats().discarded_bytes, 5 * garbage.size());
  EXPECT_EQ(parser.stats().checksum_errors, 0U);
  EXPECT_EQ(parser.buffered_bytes(), 0U);
  expect_bytes_accounted(parser, items);
}

TEST(YdlidarG4StreamParser, ACorruptedPacketIsDroppedAndCountedAndTheNextIsParsed) {
  for (std::size_t spoiled_byte = 2; spoiled_byte < kCloudPacket.size(); ++spoiled_byte) {
    Bytes bad = kCloudPacket;
    bad[spoiled_byte] ^= 0x10;
    // Ten good packets behind it: a spoiled LSN (19) makes the parser wait for that many bytes.
    Bytes stream = concat({&kZeroPacket, &bad});
    for (int i = 0; i < 10; ++i)
      stream.insert(stream.end(), kCloudPacket.begin(), kCloudPacket.end());
    StreamParser parser;
    const auto items = parse_all(stream, parser);
    // Bit 4 of FSA's or LSA's low byte is not the check bit, so the header still passes; the
    // checksum does not.
    ASSERT_EQ(items.size(), 11U) << spoiled_byte;
    EXPECT_TRUE(std::get<ScanPacket>(items[0]).starts_scan());
    EXPECT_EQ(std::get<ScanPacket>(items[1]).checksum, 0x454A);
    EXPECT_EQ(parser.stats().checksum_errors, 1U) << spoiled_byte;
    EXPECT_EQ(parser.stats().discarded_bytes, bad.size()) << spoiled_byte;
    expect_bytes_accounted(parser, items);
  }
}

TEST(YdlidarG4StreamParser, AWrongChecksumIsNeverYielded) {
  Bytes bad = kCloudPacket;
  bad[8] ^= 0x01;  // CS itself
  StreamParser parser;
  const auto items = parse_all(concat({&bad, &bad, &kCloudPacket, &bad}), parser);
  ASSERT_EQ(items.size(), 1U);
  EXPECT_EQ(parser.stats().scan_packets, 1U);
  EXPECT_EQ(parser.stats().checksum_errors, 3U);
  expect_bytes_accounted(parser, items);
}

TEST(YdlidarG4StreamParser, APacketCutShortDoesNotTakeTheNextWithIt) {
  // The first packet loses its last sample: its LSN now reaches into the next packet.
  const Bytes cut(kCloudPacket.begin(), kCloudPacket.end() - 2);
  const Bytes stream = concat({&cut, &kCloudPacket, &kZeroPacket});
  StreamParser parser;
  const auto items = parse_all(stream, parser);
  ASSERT_EQ(items.size(), 2U);
  EXPECT_FALSE(std::get<ScanPacket>(items[0]).starts_scan());
  EXPECT_TRUE(std::get<ScanPacket>(items[1]).starts_scan());
  EXPECT_EQ(parser.stats().checksum_errors, 1U);
  EXPECT_EQ(parser.stats().discarded_bytes, cut.size());

  // An LSN spoiled upwards makes the parser wait for bytes that belong to later packets; when
  // they come and the checksum fails, it goes back to the byte after the false start.
  Bytes long_lsn = kCloudPacket;
  long_lsn[3] = 80;
  Bytes many = long_lsn;
  for (int i = 0; i < 20; ++i) many.insert(many.end(), kCloudPacket.begin(), kCloudPacket.end());
  StreamParser waiting;
  const auto after = parse_all(many, waiting);
  EXPECT_EQ(after.size(), 20U);
  EXPECT_EQ(waiting.stats().checksum_errors, 1U);
  expect_bytes_accounted(waiting, after);
}

TEST(YdlidarG4StreamParser, DeviceInfoAndHealthResponses) {
  const Bytes garbage = {0x12, 0x34};
  const Bytes stream = concat({&kDeviceInfoResponse, &garbage, &kHealthResponse});
  StreamParser parser;
  std::vector<StreamItem> items;
  for (const std::uint8_t byte : stream) parser.feed(std::span(&byte, 1), items);
  ASSERT_EQ(items.size(), 2U);
  const auto& info = std::get<Response>(items[0]);
  EXPECT_EQ(info.header.type, kTypeDeviceInfo);
  ASSERT_TRUE(decode_device_info(info.payload).has_value());
  EXPECT_EQ(decode_device_info(info.payload)->model, kG4ModelCode);
  const auto& health = std::get<Response>(items[1]);
  EXPECT_EQ(health.header.type, kTypeHealth);
  EXPECT_EQ(decode_health(health.payload)->error_code, 0x1234);
  EXPECT_EQ(parser.stats().responses, 2U);
  EXPECT_EQ(parser.stats().discarded_bytes, 2U);
}

TEST(YdlidarG4StreamParser, TheBufferStaysBounded) {
  StreamParser parser;
  std::vector<StreamItem> items;
  // Endless false starts: every byte could open a packet.
  const Bytes syncs(100000, 0xAA);
  parser.feed(syncs, items);
  EXPECT_LE(parser.buffered_bytes(), 1U);
  // One large chunk of many packets goes through a bounded buffer all the same.
  Bytes many;
  for (int i = 0; i < 5000; ++i) many.insert(many.end(), kCloudPacket.begin(), kCloudPacket.end());
  parser.feed(many, items);
  EXPECT_EQ(items.size(), 5000U);
  EXPECT_EQ(parser.buffered_bytes(), 0U);
  expect_bytes_accounted(parser, items);
  parser.feed(std::span(kCloudPacket).first(7), items);
  EXPECT_EQ(parser.buffered_bytes(), 7U);
  parser.reset();
  EXPECT_EQ(parser.buffered_bytes(), 0U);
  expect_bytes_accounted(parser, items);
}

ScanPacket packet_with(std::uint8_t ct, std::vector<Sample> samples) {
  ScanPacket packet;
  packet.ct = ct;
  packet.samples = std::move(samples);
  return packet;
}

TEST(YdlidarG4ScanAssembler, TheNextZeroPacketClosesTheTurn) {
  ScanAssembler assembler;
  // Before the first zero packet: part of a turn, dropped.
  EXPECT_FALSE(assembler.add(packet_with(0x00, {{100.0, 1.0, 0}})));
  EXPECT_FALSE(assembler.add(packet_with(0x01, {{0.5, 2.0, 0}})));
  EXPECT_FALSE(assembler.add(packet_with(0x00, {{90.0, 3.0, 0}, {180.0, 4.0, 0}})));
  EXPECT_FALSE(assembler.add(packet_with(0x00, {{270.0, 5.0, 0}})));
  const auto turn = assembler.add(packet_with(0x01 | 70 << 1, {{0.2, 6.0, 0}}));
  ASSERT_TRUE(turn.has_value());
  ASSERT_EQ(turn->samples.size(), 4U);
  EXPECT_EQ(turn->samples.front().range_m, 2.0);
  EXPECT_EQ(turn->samples.back().range_m, 5.0);
  EXPECT_EQ(turn->packets, 3U);
  EXPECT_DOUBLE_EQ(*turn->scan_frequency_hz, 7.0);

  const auto next = assembler.add(packet_with(0x01, {{0.1, 7.0, 0}}));
  ASSERT_TRUE(next.has_value());
  ASSERT_EQ(next->samples.size(), 1U);
  EXPECT_EQ(next->samples[0].range_m, 6.0);
  EXPECT_FALSE(next->scan_frequency_hz.has_value());
}

TEST(YdlidarG4ScanAssembler, ATurnWithoutEndIsDropped) {
  ScanAssembler assembler({.max_samples = 10});
  assembler.add(packet_with(0x01, {{0.0, 1.0, 0}}));
  for (int i = 0; i < 5; ++i) {
    EXPECT_FALSE(assembler.add(packet_with(0x00, {{1.0, 1.0, 0}, {2.0, 1.0, 0}, {3.0, 1.0, 0}})));
  }
  EXPECT_EQ(assembler.dropped_turns(), 1U);
  // The turn after the next zero packet is whole again.
  assembler.add(packet_with(0x01, {{0.0, 1.0, 0}}));
  const auto turn = assembler.add(packet_with(0x01, {{0.0, 1.0, 0}}));
  ASSERT_TRUE(turn.has_value());
  EXPECT_EQ(turn->samples.size(), 1U);
}

TEST(YdlidarG4LaserScan, TheFrameIsTheRosDriversCounterClockwiseOne) {
  // Clockwise from the cable on the device; counter-clockwise from the opposite side in mobot.
  EXPECT_NEAR(sensor_angle_rad(180.0), 0.0, 1e-12);
  EXPECT_NEAR(sensor_angle_rad(90.0), std::numbers::pi / 2.0, 1e-12);
  EXPECT_NEAR(sensor_angle_rad(270.0), -std::numbers::pi / 2.0, 1e-12);
  EXPECT_NEAR(std::abs(sensor_angle_rad(0.0)), std::numbers::pi, 1e-12);
  for (const double deg : {0.0, 1.5, 90.0, 179.0, 181.0, 359.9}) {
    EXPECT_NEAR(device_angle_deg(sensor_angle_rad(deg)), deg, 1e-9) << deg;
  }
}

TEST(YdlidarG4LaserScan, BinsAndNoReturns) {
  Scan scan;
  scan.samples = {
      {180.0, 3.0, 0},  // straight ahead: bin 360 of 720
      {180.2, 2.5, 0},  // same bin (within 0.25 deg): the nearer wins
      {90.0, 1.0, 0},   // left, +pi/2: bin 540
      {270.0, 0.0, 0},  // right, -pi/2: bin 180, no return
      {0.0, 12.0, 0},   // behind: bin 0, beyond range_max 10
      {45.0, 0.05, 0},  // nearer than range_min: says nothing, bin 630 stays 0
      {135.0, 0.0, 0},  // bin 450: no return ...
      {135.1, 4.0, 0},  // ... but a return in the same bin wins
  };
  const geometry::Pose2D mount{0.1, -0.2, 0.3};
  const msgs::LaserScan laser = to_laser_scan(
      scan, {.bin_count = 720, .range_min_m = 0.1, .range_max_m = 10.0, .sensor_in_base = mount},
      12.5);
  EXPECT_EQ(laser.stamp_s, 12.5);
  EXPECT_FLOAT_EQ(laser.angle_min_rad, static_cast<float>(-std::numbers::pi));
  EXPECT_FLOAT_EQ(laser.angle_increment_rad, static_cast<float>(std::numbers::pi / 360.0));
  EXPECT_FLOAT_EQ(laser.range_min_m, 0.1F);
  EXPECT_FLOAT_EQ(laser.range_max_m, 10.0F);
  EXPECT_EQ(laser.sensor_in_base, mount);
  ASSERT_EQ(laser.ranges_m.size(), 720U);
  constexpr float kInf = std::numeric_limits<float>::infinity();
  EXPECT_FLOAT_EQ(laser.ranges_m[360], 2.5F);
  EXPECT_FLOAT_EQ(laser.ranges_m[540], 1.0F);
  EXPECT_EQ(laser.ranges_m[180], kInf);
  EXPECT_EQ(laser.ranges_m[0], kInf);
  EXPECT_EQ(laser.ranges_m[630], 0.0F);
  EXPECT_FLOAT_EQ(laser.ranges_m[450], 4.0F);
  int untouched = 0;
  for (const float range_m : laser.ranges_m) untouched += range_m == 0.0F ? 1 : 0;
  EXPECT_EQ(untouched, 720 - 5);

  // Beam i points at angle_min + i * increment: bin 540's angle is the sample's, +pi/2.
  EXPECT_NEAR(laser.angle_min_rad + 540 * laser.angle_increment_rad, std::numbers::pi / 2.0, 1e-5);
}

TEST(YdlidarG4LaserScan, DegenerateOptions) {
  Scan scan;
  scan.samples = {{10.0, 1.0, 0}, {std::numeric_limits<double>::quiet_NaN(), 1.0, 0}};
  LaserScanOptions options;
  options.bin_count = 0;
  const auto one_bin = to_laser_scan(scan, options, 0.0);
  ASSERT_EQ(one_bin.ranges_m.size(), 1U);
  EXPECT_FLOAT_EQ(one_bin.ranges_m[0], 1.0F);
  options = LaserScanOptions{};
  options.range_min_m = 5.0;
  options.range_max_m = 1.0;
  const auto inverted = to_laser_scan(scan, options, 0.0);
  for (const float range_m : inverted.ranges_m) EXPECT_EQ(range_m, 0.0F);
}

TEST(YdlidarG4Pipeline, ParsedPacketsBecomeALaserScan) {
  // Two turns of hand-built packets: a wall 1000 mm away around device angle 90 (the left).
  Bytes stream;
  for (int turn = 0; turn < 3; ++turn) {
    const std::vector<RawSample> zero = {{0, 0}};
    const Bytes zero_packet = encode_scan_packet(
        0x01, angle_raw_from_deg(0.0), angle_raw_from_deg(0.0), zero, SampleFormat::kDistance);
    stream.insert(stream.end(), zero_packet.begin(), zero_packet.end());
    // The raw angle of each sample is 90 deg minus the correction the host will add.
    const double raw_deg = 90.0 - angle_correction_deg(1000.0);
    const std::vector<RawSample> wall = {{4000, 0}, {4000, 0}};
    const Bytes wall_packet =
        encode_scan_packet(0x00, angle_raw_from_deg(raw_deg), angle_raw_from_deg(raw_deg + 0.25),
                           wall, SampleFormat::kDistance);
    stream.insert(stream.end(), wall_packet.begin(), wall_packet.end());
  }
  StreamParser parser;
  ScanAssembler assembler;
  std::vector<Scan> scans;
  for (const StreamItem& item : parse_all(stream, parser)) {
    if (auto turn = assembler.add(std::get<ScanPacket>(item))) scans.push_back(std::move(*turn));
  }
  ASSERT_EQ(scans.size(), 2U);
  const msgs::LaserScan laser = to_laser_scan(scans[0], {}, 0.0);
  EXPECT_FLOAT_EQ(laser.ranges_m[540], 1.0F);
  EXPECT_EQ(laser.ranges_m[0], std::numeric_limits<float>::infinity());
}

}  // namespace
}  // namespace mobot::protocol::ydlidar
