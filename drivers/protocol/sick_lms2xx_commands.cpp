#include "drivers/protocol/sick_lms2xx_commands.h"

#include <array>
#include <initializer_list>
#include <utility>

namespace mobot::protocol::sick {
namespace {

constexpr std::size_t kPasswordBytes = 8;

// Offsets into the 154-byte status payload (command byte at 0).
constexpr std::size_t kVersionAt = 1;
constexpr std::size_t kVersionBytes = 7;
constexpr std::size_t kOperatingModeAt = 8;
constexpr std::size_t kDeviceErrorAt = 9;
constexpr std::size_t kMeasuringModeAt = 102;
constexpr std::size_t kAngleAt = 107;
constexpr std::size_t kResolutionAt = 109;
constexpr std::size_t kBaudWordAt = 116;
constexpr std::size_t kUnitsAt = 122;

// The status block gives the line rate as a divider word: 0x8000 | (1 MHz / rate - 1).
constexpr std::array<std::pair<int, std::uint16_t>, 4> kBaudWords{{
    {9600, 0x8067},
    {19200, 0x8033},
    {38400, 0x8019},
    {500000, 0x8001},
}};

std::uint16_t read_u16(const std::vector<std::uint8_t>& bytes, std::size_t at) {
  return static_cast<std::uint16_t>(bytes[at] | (bytes[at + 1] << 8U));
}

void write_u16(std::vector<std::uint8_t>& bytes, std::size_t at, std::uint16_t value) {
  bytes[at] = static_cast<std::uint8_t>(value & 0xFFU);
  bytes[at + 1] = static_cast<std::uint8_t>(value >> 8U);
}

std::vector<std::uint8_t> request(std::initializer_list<std::uint8_t> payload) {
  return encode_telegram(kLmsAddress, std::vector<std::uint8_t>(payload));
}

}  // namespace

int bits_per_second(BaudRate rate) {
  switch (rate) {
    case BaudRate::k9600:
      return 9600;
    case BaudRate::k19200:
      return 19200;
    case BaudRate::k38400:
      return 38400;
    case BaudRate::k500000:
      return 500000;
  }
  return 0;
}

std::optional<BaudRate> baud_rate_from_bps(int bits_per_second) {
  for (const BaudRate rate :
       {BaudRate::k9600, BaudRate::k19200, BaudRate::k38400, BaudRate::k500000}) {
    if (sick::bits_per_second(rate) == bits_per_second) return rate;
  }
  return std::nullopt;
}

bool is_supported(const Variant& variant) {
  return !(variant.angle == ScanAngle::k180Deg &&
           variant.resolution == AngularResolution::kQuarterDeg);
}

std::optional<Variant> variant_from(std::uint16_t angle_deg, std::uint16_t resolution_cdeg) {
  Variant variant;
  if (angle_deg == 100) {
    variant.angle = ScanAngle::k100Deg;
  } else if (angle_deg == 180) {
    variant.angle = ScanAngle::k180Deg;
  } else {
    return std::nullopt;
  }
  if (resolution_cdeg == 25) {
    variant.resolution = AngularResolution::kQuarterDeg;
  } else if (resolution_cdeg == 50) {
    variant.resolution = AngularResolution::kHalfDeg;
  } else if (resolution_cdeg == 100) {
    variant.resolution = AngularResolution::kOneDeg;
  } else {
    return std::nullopt;
  }
  return variant;
}

std::size_t values_per_scan(const Variant& variant) {
  return static_cast<std::size_t>(variant.angle) * 100U /
             static_cast<std::size_t>(variant.resolution) +
         1U;
}

int rotations_per_scan(AngularResolution resolution) { return 100 / static_cast<int>(resolution); }

double resolution_deg(AngularResolution resolution) {
  return static_cast<double>(resolution) / 100.0;
}

double metres_per_unit(MeasuringUnits units) {
  return units == MeasuringUnits::kMillimetres ? 0.001 : 0.01;
}

std::vector<std::uint8_t> mode_switch_request(OperatingMode mode) {
  if (mode == OperatingMode::kInstallation) return installation_mode_request(kDefaultPassword);
  return request({kModeSwitchCommand, static_cast<std::uint8_t>(mode)});
}

std::vector<std::uint8_t> installation_mode_request(std::string_view password) {
  std::vector<std::uint8_t> payload{kModeSwitchCommand,
                                    static_cast<std::uint8_t>(OperatingMode::kInstallation)};
  for (std::size_t i = 0; i < kPasswordBytes; ++i) {
    payload.push_back(i < password.size() ? static_cast<std::uint8_t>(password[i]) : ' ');
  }
  return encode_telegram(kLmsAddress, payload);
}

std::vector<std::uint8_t> baud_rate_request(BaudRate rate) {
  return request({kModeSwitchCommand, static_cast<std::uint8_t>(rate)});
}

std::vector<std::uint8_t> variant_request(const Variant& variant) {
  const auto angle = static_cast<std::uint16_t>(variant.angle);
  const auto resolution = static_cast<std::uint16_t>(variant.resolution);
  return request({kVariantCommand, static_cast<std::uint8_t>(angle & 0xFFU),
                  static_cast<std::uint8_t>(angle >> 8U),
                  static_cast<std::uint8_t>(resolution & 0xFFU),
                  static_cast<std::uint8_t>(resolution >> 8U)});
}

std::vector<std::uint8_t> status_request() { return request({kStatusCommand}); }

std::optional<ModeSwitchReply> parse_mode_switch_reply(const Telegram& telegram) {
  const std::vector<std::uint8_t>& p = telegram.payload;
  if (p.size() != 3 || p[0] != kModeSwitchReply) return std::nullopt;
  return ModeSwitchReply{p[1], p[2]};
}

std::optional<VariantReply> parse_variant_reply(const Telegram& telegram) {
  const std::vector<std::uint8_t>& p = telegram.payload;
  if (p.size() != 7 || p[0] != kVariantReply) return std::nullopt;
  VariantReply reply;
  reply.accepted = p[1] == 0x01;
  reply.angle_deg = read_u16(p, 2);
  reply.resolution_cdeg = read_u16(p, 4);
  reply.status = p[6];
  return reply;
}

std::optional<MeasuringUnits> StatusReply::units() const {
  if (units_code == static_cast<std::uint8_t>(MeasuringUnits::kCentimetres)) {
    return MeasuringUnits::kCentimetres;
  }
  if (units_code == static_cast<std::uint8_t>(MeasuringUnits::kMillimetres)) {
    return MeasuringUnits::kMillimetres;
  }
  return std::nullopt;
}

std::optional<StatusReply> parse_status_reply(const Telegram& telegram) {
  const std::vector<std::uint8_t>& p = telegram.payload;
  if (p.size() != kStatusReplyPayloadBytes || p[0] != kStatusReply) return std::nullopt;
  StatusReply reply;
  reply.software_version.assign(p.begin() + kVersionAt, p.begin() + kVersionAt + kVersionBytes);
  reply.operating_mode = p[kOperatingModeAt];
  reply.device_error = p[kDeviceErrorAt];
  reply.measuring_mode = p[kMeasuringModeAt];
  reply.angle_deg = read_u16(p, kAngleAt);
  reply.resolution_cdeg = read_u16(p, kResolutionAt);
  const std::uint16_t baud_word = read_u16(p, kBaudWordAt);
  for (const auto& [bps, word] : kBaudWords) {
    if (word == baud_word) reply.baud_bps = bps;
  }
  reply.units_code = p[kUnitsAt];
  reply.status = p.back();
  return reply;
}

std::vector<std::uint8_t> mode_switch_reply(const ModeSwitchReply& reply) {
  const std::vector<std::uint8_t> payload{kModeSwitchReply, reply.result, reply.status};
  return encode_telegram(kReplyAddress, payload);
}

std::vector<std::uint8_t> variant_reply(const VariantReply& reply) {
  std::vector<std::uint8_t> payload(7, 0);
  payload[0] = kVariantReply;
  payload[1] = reply.accepted ? 0x01 : 0x00;
  write_u16(payload, 2, reply.angle_deg);
  write_u16(payload, 4, reply.resolution_cdeg);
  payload[6] = reply.status;
  return encode_telegram(kReplyAddress, payload);
}

std::vector<std::uint8_t> status_reply(const StatusReply& reply) {
  std::vector<std::uint8_t> payload(kStatusReplyPayloadBytes, 0);
  payload[0] = kStatusReply;
  for (std::size_t i = 0; i < kVersionBytes; ++i) {
    payload[kVersionAt + i] = i < reply.software_version.size()
                                  ? static_cast<std::uint8_t>(reply.software_version[i])
                                  : ' ';
  }
  payload[kOperatingModeAt] = reply.operating_mode;
  payload[kDeviceErrorAt] = reply.device_error;
  payload[kMeasuringModeAt] = reply.measuring_mode;
  write_u16(payload, kAngleAt, reply.angle_deg);
  write_u16(payload, kResolutionAt, reply.resolution_cdeg);
  for (const auto& [bps, word] : kBaudWords) {
    if (bps == reply.baud_bps) write_u16(payload, kBaudWordAt, word);
  }
  payload[kUnitsAt] = reply.units_code;
  payload.back() = reply.status;
  return encode_telegram(kReplyAddress, payload);
}

std::vector<std::uint8_t> not_acknowledged_reply(std::uint8_t status) {
  const std::vector<std::uint8_t> payload{kNotAcknowledgedReply, status};
  return encode_telegram(kReplyAddress, payload);
}

}  // namespace mobot::protocol::sick
