#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/protocol/sick_lms2xx_telegram.h"

namespace mobot::protocol::sick {

// Command bytes. A reply carries its request's command with the top bit set; measured values
// (requested or streamed) come as 0xB0; 0x92 answers a command the LMS does not accept.
inline constexpr std::uint8_t kModeSwitchCommand = 0x20;
inline constexpr std::uint8_t kStatusCommand = 0x31;
inline constexpr std::uint8_t kVariantCommand = 0x3B;
inline constexpr std::uint8_t kModeSwitchReply = 0xA0;
inline constexpr std::uint8_t kMeasuredValuesReply = 0xB0;
inline constexpr std::uint8_t kStatusReply = 0xB1;
inline constexpr std::uint8_t kVariantReply = 0xBB;
inline constexpr std::uint8_t kNotAcknowledgedReply = 0x92;

// The operating modes this codec builds requests for (the mode byte of command 0x20).
enum class OperatingMode : std::uint8_t {
  kInstallation = 0x00,  // needs the password; where the configuration can be changed
  kContinuousAllValues = 0x24,
  kOnRequest = 0x25,  // values only when asked for: what stops continuous output
  // One telegram per mirror rotation (180 deg at 1 deg steps, offset by a multiple of 0.25 deg):
  // the parts of an interlaced 0.5 or 0.25 deg scan, as they are measured.
  kContinuousPartialScans = 0x2A,
};

// The line rates, as the mode bytes of command 0x20 that switch to them. The LMS answers at the
// old rate and talks at the new one from then on. After power-on it talks at 9600 baud.
enum class BaudRate : std::uint8_t {
  k9600 = 0x42,
  k19200 = 0x41,
  k38400 = 0x40,
  k500000 = 0x48,
};
int bits_per_second(BaudRate rate);
std::optional<BaudRate> baud_rate_from_bps(int bits_per_second);

enum class ScanAngle : std::uint16_t { k100Deg = 100, k180Deg = 180 };
// In hundredths of a degree, as the variant telegrams carry it.
enum class AngularResolution : std::uint16_t { kQuarterDeg = 25, kHalfDeg = 50, kOneDeg = 100 };

struct Variant {
  ScanAngle angle = ScanAngle::k180Deg;
  AngularResolution resolution = AngularResolution::kOneDeg;

  bool operator==(const Variant&) const = default;
};
// 180 deg at 0.25 deg is no variant: a complete scan would take four rotations and 721 values.
// The LMS refuses it; 180 deg at 0.25 deg exists only as interlaced parts (kContinuousPartialScans
// with a 0.25 deg variant).
bool is_supported(const Variant& variant);
std::optional<Variant> variant_from(std::uint16_t angle_deg, std::uint16_t resolution_cdeg);
// Values in one complete scan: angle / resolution + 1 (181, 361, 101, 201, 401).
std::size_t values_per_scan(const Variant& variant);
// Mirror rotations the LMS interlaces into one complete scan: 1, 2 or 4.
int rotations_per_scan(AngularResolution resolution);
double resolution_deg(AngularResolution resolution);

enum class MeasuringUnits : std::uint8_t { kCentimetres = 0, kMillimetres = 1 };
double metres_per_unit(MeasuringUnits units);

inline constexpr std::string_view kDefaultPassword = "SICK_LMS";

// The host's requests, complete telegrams to kLmsAddress. Each gets ACK (or NAK) and a reply.
// kInstallation goes with the default password.
std::vector<std::uint8_t> mode_switch_request(OperatingMode mode);
// The LMS password is 8 characters; a longer one is cut, a shorter one padded with spaces.
std::vector<std::uint8_t> installation_mode_request(std::string_view password = kDefaultPassword);
std::vector<std::uint8_t> baud_rate_request(BaudRate rate);
std::vector<std::uint8_t> variant_request(const Variant& variant);
std::vector<std::uint8_t> status_request();

// Reply 0xA0 to a mode or baud-rate switch.
inline constexpr std::uint8_t kModeSwitchAccepted = 0x00;
inline constexpr std::uint8_t kModeSwitchWrongPassword = 0x01;
inline constexpr std::uint8_t kModeSwitchFault = 0x02;
struct ModeSwitchReply {
  std::uint8_t result = kModeSwitchAccepted;
  std::uint8_t status = 0;

  bool accepted() const { return result == kModeSwitchAccepted; }
  bool operator==(const ModeSwitchReply&) const = default;
};
std::optional<ModeSwitchReply> parse_mode_switch_reply(const Telegram& telegram);

// Reply 0xBB: whether the variant was taken, then the variant in force.
struct VariantReply {
  bool accepted = false;
  std::uint16_t angle_deg = 0;
  std::uint16_t resolution_cdeg = 0;
  std::uint8_t status = 0;

  std::optional<Variant> variant() const { return variant_from(angle_deg, resolution_cdeg); }
  bool operator==(const VariantReply&) const = default;
};
std::optional<VariantReply> parse_variant_reply(const Telegram& telegram);

// Reply 0xB1, the fields a driver needs from the 154-byte payload (command, 152 bytes of status,
// status byte) of LMS2xx firmware with the long status block. Older firmware sends a shorter
// block with the later fields moved; it is not parsed.
inline constexpr std::size_t kStatusReplyPayloadBytes = 154;
struct StatusReply {
  std::string software_version;  // 7 characters, e.g. "V02.10 "
  std::uint8_t operating_mode = 0;
  std::uint8_t device_error = 0;  // 0: none
  std::uint8_t measuring_mode = 0;
  std::uint16_t angle_deg = 0;
  std::uint16_t resolution_cdeg = 0;
  int baud_bps = 0;  // 0 when the rate word is not one of the four rates
  std::uint8_t units_code = 0;
  std::uint8_t status = 0;

  std::optional<MeasuringUnits> units() const;
  bool operator==(const StatusReply&) const = default;
};
std::optional<StatusReply> parse_status_reply(const Telegram& telegram);

// The device's replies, complete telegrams from kReplyAddress (for an emulated LMS and tests).
std::vector<std::uint8_t> mode_switch_reply(const ModeSwitchReply& reply);
std::vector<std::uint8_t> variant_reply(const VariantReply& reply);
std::vector<std::uint8_t> status_reply(const StatusReply& reply);
std::vector<std::uint8_t> not_acknowledged_reply(std::uint8_t status);

}  // namespace mobot::protocol::sick
