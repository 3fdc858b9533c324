#include "drivers/protocol/ydlidar_g4.h"

#include <cmath>
#include <numbers>

namespace mobot::protocol::ydlidar {
namespace {

constexpr std::uint32_t kLengthMask = 0x3FFFFFFFU;
constexpr int kAngleUnitsPerDegree = 64;
constexpr int kAngleUnitsPerTurn = 360 * kAngleUnitsPerDegree;

std::uint16_t word_at(std::span<const std::uint8_t> bytes, std::size_t offset) {
  return static_cast<std::uint16_t>(bytes[offset] | (bytes[offset + 1] << 8));
}

std::uint32_t dword_at(std::span<const std::uint8_t> bytes, std::size_t offset) {
  return static_cast<std::uint32_t>(bytes[offset]) |
         static_cast<std::uint32_t>(bytes[offset + 1]) << 8 |
         static_cast<std::uint32_t>(bytes[offset + 2]) << 16 |
         static_cast<std::uint32_t>(bytes[offset + 3]) << 24;
}

void put_word(std::uint8_t* out, std::uint16_t value) {
  out[0] = static_cast<std::uint8_t>(value & 0xFF);
  out[1] = static_cast<std::uint8_t>(value >> 8);
}

std::size_t packet_bytes(std::size_t sample_count, SampleFormat format) {
  return kScanHeaderBytes + sample_count * sample_bytes(format);
}

std::uint16_t intensity_of(const RawSample& raw, SampleFormat format) {
  switch (format) {
    case SampleFormat::kDistance:
      return 0;
    case SampleFormat::kIntensity8:
      return raw.intensity_raw;
    case SampleFormat::kIntensity10:
      return static_cast<std::uint16_t>(raw.intensity_raw | (raw.distance_raw & 0x03) << 8);
  }
  return 0;
}

}  // namespace

std::array<std::uint8_t, kCommandBytes> encode_command(Command command) {
  return {kCommandSync, static_cast<std::uint8_t>(command)};
}

std::array<std::uint8_t, kResponseHeaderBytes> encode_response_header(
    const ResponseHeader& header) {
  const std::uint32_t word = (header.length & kLengthMask) |
                             static_cast<std::uint32_t>(static_cast<std::uint8_t>(header.mode))
                                 << 30;
  return {kResponseSync1,
          kResponseSync2,
          static_cast<std::uint8_t>(word & 0xFF),
          static_cast<std::uint8_t>(word >> 8 & 0xFF),
          static_cast<std::uint8_t>(word >> 16 & 0xFF),
          static_cast<std::uint8_t>(word >> 24),
          header.type};
}

std::optional<ResponseHeader> decode_response_header(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kResponseHeaderBytes || bytes[0] != kResponseSync1 ||
      bytes[1] != kResponseSync2) {
    return std::nullopt;
  }
  const std::uint32_t word = dword_at(bytes, 2);
  const std::uint32_t mode = word >> 30;
  if (mode > 1) return std::nullopt;
  return ResponseHeader{word & kLengthMask, static_cast<ResponseMode>(mode), bytes[6]};
}

bool is_known_response(const ResponseHeader& header) {
  if (header.mode == ResponseMode::kContinuous) return header.type == kTypeScan;
  if (header.type == kTypeHealth) return header.length == kHealthBytes;
  if (header.type == kTypeDeviceInfo) {
    return header.length == kDeviceInfoBytes || header.length == kScanFrequencyBytes ||
           header.length == kSamplingRateBytes;
  }
  return false;
}

std::array<std::uint8_t, kDeviceInfoBytes> encode_device_info(const DeviceInfo& info) {
  std::array<std::uint8_t, kDeviceInfoBytes> out{};
  out[0] = info.model;
  out[1] = info.firmware_minor;
  out[2] = info.firmware_major;
  out[3] = info.hardware;
  for (std::size_t i = 0; i < info.serial.size(); ++i) out[4 + i] = info.serial[i];
  return out;
}

std::optional<DeviceInfo> decode_device_info(std::span<const std::uint8_t> payload) {
  if (payload.size() != kDeviceInfoBytes) return std::nullopt;
  DeviceInfo info;
  info.model = payload[0];
  info.firmware_minor = payload[1];
  info.firmware_major = payload[2];
  info.hardware = payload[3];
  for (std::size_t i = 0; i < info.serial.size(); ++i) info.serial[i] = payload[4 + i];
  return info;
}

std::string serial_number_text(const DeviceInfo& info) {
  std::string text;
  for (const std::uint8_t digit : info.serial) text += std::to_string(digit);
  return text;
}

std::array<std::uint8_t, kHealthBytes> encode_health(const Health& health) {
  return {health.status, static_cast<std::uint8_t>(health.error_code & 0xFF),
          static_cast<std::uint8_t>(health.error_code >> 8)};
}

std::optional<Health> decode_health(std::span<const std::uint8_t> payload) {
  if (payload.size() != kHealthBytes) return std::nullopt;
  return Health{payload[0], word_at(payload, 1)};
}

std::optional<double> decode_scan_frequency_hz(std::span<const std::uint8_t> payload) {
  if (payload.size() != kScanFrequencyBytes) return std::nullopt;
  return static_cast<double>(dword_at(payload, 0)) / 100.0;
}

std::optional<int> decode_sampling_rate_hz(std::span<const std::uint8_t> payload) {
  if (payload.size() != kSamplingRateBytes) return std::nullopt;
  switch (payload[0]) {
    case 0:
      return 4000;
    case 1:
      return 8000;
    case 2:
      return 9000;
    default:
      return std::nullopt;
  }
}

std::optional<std::uint8_t> sampling_rate_code(int sampling_rate_hz) {
  switch (sampling_rate_hz) {
    case 4000:
      return 0;
    case 8000:
      return 1;
    case 9000:
      return 2;
    default:
      return std::nullopt;
  }
}

std::size_t sample_bytes(SampleFormat format) { return format == SampleFormat::kDistance ? 2 : 3; }

std::uint16_t scan_checksum(std::span<const std::uint8_t> packet, SampleFormat format) {
  if (packet.size() < kScanHeaderBytes) return 0;
  const std::size_t count = packet[3];
  if (packet.size() < packet_bytes(count, format)) return 0;
  // The order is the manual's; XOR does not care.
  std::uint16_t cs = word_at(packet, 0);  // PH
  cs ^= word_at(packet, 4);               // FSA
  std::size_t offset = kScanHeaderBytes;
  for (std::size_t i = 0; i < count; ++i) {
    if (format != SampleFormat::kDistance) cs ^= packet[offset++];
    cs ^= word_at(packet, offset);
    offset += 2;
  }
  cs ^= word_at(packet, 2);  // CT | LSN << 8
  cs ^= word_at(packet, 6);  // LSA
  return cs;
}

std::vector<std::uint8_t> encode_scan_packet(std::uint8_t ct, std::uint16_t first_angle_raw,
                                             std::uint16_t last_angle_raw,
                                             std::span<const RawSample> samples,
                                             SampleFormat format, std::uint16_t checksum_xor) {
  if (samples.empty() || samples.size() > kMaxSamplesPerPacket) return {};
  std::vector<std::uint8_t> out(packet_bytes(samples.size(), format));
  out[0] = kPacketSync1;
  out[1] = kPacketSync2;
  out[2] = ct;
  out[3] = static_cast<std::uint8_t>(samples.size());
  put_word(&out[4], first_angle_raw);
  put_word(&out[6], last_angle_raw);
  std::size_t offset = kScanHeaderBytes;
  for (const RawSample& sample : samples) {
    if (format != SampleFormat::kDistance) out[offset++] = sample.intensity_raw;
    put_word(&out[offset], sample.distance_raw);
    offset += 2;
  }
  put_word(&out[8], static_cast<std::uint16_t>(scan_checksum(out, format) ^ checksum_xor));
  return out;
}

std::uint16_t angle_raw_from_deg(double angle_deg) {
  long units = std::isfinite(angle_deg) ? std::lround(angle_deg * kAngleUnitsPerDegree) : 0;
  units %= kAngleUnitsPerTurn;
  if (units < 0) units += kAngleUnitsPerTurn;
  return static_cast<std::uint16_t>(units << 1 | 1);
}

double angle_deg_from_raw(std::uint16_t angle_raw) {
  return static_cast<double>(angle_raw >> 1) / kAngleUnitsPerDegree;
}

double angle_correction_deg(double distance_mm) {
  if (!(distance_mm > 0.0)) return 0.0;
  return std::atan(21.8 * (155.3 - distance_mm) / (155.3 * distance_mm)) * 180.0 / std::numbers::pi;
}

double distance_mm_from_raw(std::uint16_t distance_raw, SampleFormat format) {
  const std::uint16_t raw =
      format == SampleFormat::kDistance ? distance_raw : (distance_raw & 0xFFFC);
  return raw / 4.0;
}

std::optional<double> ScanPacket::scan_frequency_hz() const {
  if (!starts_scan() || (ct >> 1) == 0) return std::nullopt;
  return (ct >> 1) / 10.0;
}

std::optional<ScanPacket> decode_scan_packet(std::span<const std::uint8_t> packet,
                                             SampleFormat format) {
  if (packet.size() < kScanHeaderBytes || packet[0] != kPacketSync1 || packet[1] != kPacketSync2) {
    return std::nullopt;
  }
  const std::size_t count = packet[3];
  if (count == 0 || count > kMaxSamplesPerPacket || packet.size() != packet_bytes(count, format)) {
    return std::nullopt;
  }
  ScanPacket out;
  out.ct = packet[2];
  out.first_angle_raw = word_at(packet, 4);
  out.last_angle_raw = word_at(packet, 6);
  out.checksum = word_at(packet, 8);
  const double first_deg = angle_deg_from_raw(out.first_angle_raw);
  double span_deg = angle_deg_from_raw(out.last_angle_raw) - first_deg;
  if (span_deg < 0.0) span_deg += 360.0;
  const double step_deg = count > 1 ? span_deg / static_cast<double>(count - 1) : 0.0;
  out.samples.reserve(count);
  std::size_t offset = kScanHeaderBytes;
  for (std::size_t i = 0; i < count; ++i) {
    RawSample raw;
    if (format != SampleFormat::kDistance) raw.intensity_raw = packet[offset++];
    raw.distance_raw = word_at(packet, offset);
    offset += 2;
    const double distance_mm = distance_mm_from_raw(raw.distance_raw, format);
    double angle_deg =
        first_deg + step_deg * static_cast<double>(i) + angle_correction_deg(distance_mm);
    angle_deg = std::fmod(angle_deg, 360.0);
    if (angle_deg < 0.0) angle_deg += 360.0;
    // fmod of a value just below 0 can round up to exactly 360.
    if (angle_deg >= 360.0) angle_deg = 0.0;
    out.samples.push_back({angle_deg, distance_mm / 1000.0, intensity_of(raw, format)});
  }
  return out;
}

}  // namespace mobot::protocol::ydlidar
