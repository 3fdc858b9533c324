#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

// The serial protocol of the YDLIDAR G4 (230400 baud, 8N1, little-endian throughout).
//
// Host to device: two bytes, A5 and a command code; no payload, no checksum.
// Device to host:
//   - a response: A5 5A, a 32-bit word (low 30 bits length, high 2 bits mode: 0 single, 1
//     continuous), a type byte, then `length` payload bytes for a single response. The start-scan
//     response is continuous (A5 5A 05 00 00 40 81): its length means nothing, scan packets follow.
//   - scan packets: PH (AA 55), CT, LSN, FSA (2), LSA (2), CS (2), LSN samples. CT bit 0 marks the
//     packet that starts a new turn (LSN = 1: the zero packet); FSA and LSA are the raw angles of
//     the first and last sample, each (angle_deg * 64) << 1 | 1; a sample is the distance word Si
//     (2 bytes, Si / 4 mm) or, on the intensity variants, an intensity byte then Si.
namespace mobot::protocol::ydlidar {

inline constexpr std::uint8_t kCommandSync = 0xA5;
inline constexpr std::uint8_t kResponseSync1 = 0xA5;
inline constexpr std::uint8_t kResponseSync2 = 0x5A;
inline constexpr std::uint8_t kPacketSync1 = 0xAA;
inline constexpr std::uint8_t kPacketSync2 = 0x55;
inline constexpr std::uint16_t kPacketHeaderWord = 0x55AA;  // PH read little-endian

inline constexpr std::size_t kCommandBytes = 2;
inline constexpr std::size_t kResponseHeaderBytes = 7;
inline constexpr std::size_t kScanHeaderBytes = 10;
// The SDK refuses more samples per packet; 80 is the G4's maximum (the other triangulation models
// send at most 40).
inline constexpr std::size_t kMaxSamplesPerPacket = 80;

inline constexpr int kBaudRate = 230400;
inline constexpr std::uint8_t kG4ModelCode = 5;  // the SDK's YDLIDAR_G4

enum class Command : std::uint8_t {
  kStartScan = 0x60,
  kForceScan = 0x61,
  kStopScan = 0x65,
  // The SDK sends this before kStopScan so that a device mid-command drops it.
  kForceStop = 0x00,
  kGetDeviceInfo = 0x90,
  // The G4 manual lists A5 91; the SDK sends A5 92 to every model, the G4 included.
  kGetHealth = 0x92,
  kGetHealthManual = 0x91,
  // Soft restart, no answer. The G4 manual's code; the SDK sends A5 80.
  kRestart = 0x40,
  kRestartSdk = 0x80,
  kScanFrequencyUp0p1 = 0x09,
  kScanFrequencyDown0p1 = 0x0A,
  kScanFrequencyUp1 = 0x0B,
  kScanFrequencyDown1 = 0x0C,
  kGetScanFrequency = 0x0D,
  kGetSamplingRate = 0xD1,
};

std::array<std::uint8_t, kCommandBytes> encode_command(Command command);

enum class ResponseMode : std::uint8_t { kSingle = 0, kContinuous = 1 };

// Type codes of the responses the G4 sends.
inline constexpr std::uint8_t kTypeDeviceInfo = 0x04;  // also scan frequency and sampling rate
inline constexpr std::uint8_t kTypeHealth = 0x06;
inline constexpr std::uint8_t kTypeScan = 0x81;

inline constexpr std::size_t kDeviceInfoBytes = 20;
inline constexpr std::size_t kHealthBytes = 3;
inline constexpr std::size_t kScanFrequencyBytes = 4;
inline constexpr std::size_t kSamplingRateBytes = 1;
inline constexpr std::uint32_t kStartScanResponseLength = 5;

struct ResponseHeader {
  std::uint32_t length = 0;  // 30 bits
  ResponseMode mode = ResponseMode::kSingle;
  std::uint8_t type = 0;

  bool operator==(const ResponseHeader&) const = default;
};

std::array<std::uint8_t, kResponseHeaderBytes> encode_response_header(const ResponseHeader& header);
// Reads the 7 header bytes (sync bytes included). nullopt unless the sync bytes match and the
// mode is single or continuous; the type and length are not judged here.
std::optional<ResponseHeader> decode_response_header(std::span<const std::uint8_t> bytes);
// The headers the G4 really sends: device info (20), scan frequency (4) and sampling rate (1) as
// type 04, health (3) as type 06, each single; the start-scan answer continuous with type 81. The
// stream parser takes nothing else for a response, because a response carries no checksum and a
// stray A5 5A in noise would otherwise swallow the packets behind it.
bool is_known_response(const ResponseHeader& header);

struct DeviceInfo {
  std::uint8_t model = 0;
  std::uint8_t firmware_major = 0;
  std::uint8_t firmware_minor = 0;
  std::uint8_t hardware = 0;
  // One decimal digit per byte, as the SDK prints it.
  std::array<std::uint8_t, 16> serial{};

  bool operator==(const DeviceInfo&) const = default;
};

// Payload layout: model, firmware (16 bits: the SDK reads the high byte as the major version; the
// G4 manual says the low byte, the SDK is what real devices are read with), hardware, serial.
std::array<std::uint8_t, kDeviceInfoBytes> encode_device_info(const DeviceInfo& info);
std::optional<DeviceInfo> decode_device_info(std::span<const std::uint8_t> payload);
// The serial number as the SDK prints it: each byte in decimal, concatenated.
std::string serial_number_text(const DeviceInfo& info);

struct Health {
  std::uint8_t status = 0;  // 0 running, 1 warning, 2 error
  std::uint16_t error_code = 0;

  bool operator==(const Health&) const = default;
};

std::array<std::uint8_t, kHealthBytes> encode_health(const Health& health);
std::optional<Health> decode_health(std::span<const std::uint8_t> payload);

// Payload of A5 0D and of the frequency steps: the set scan frequency in 1/100 Hz, 32 bits.
std::optional<double> decode_scan_frequency_hz(std::span<const std::uint8_t> payload);
// Payload of A5 D1: 0 -> 4000, 1 -> 8000, 2 -> 9000 samples per second.
std::optional<int> decode_sampling_rate_hz(std::span<const std::uint8_t> payload);
// The code of a rate the G4 offers, nullopt for any other.
std::optional<std::uint8_t> sampling_rate_code(int sampling_rate_hz);

// How a sample sits on the wire. The plain G4 sends kDistance. With intensity (the SDK's
// "intensity" option) each sample is an intensity byte I then the distance word Si, Si's low two
// bits belonging to the intensity: kIntensity8 reads them as flags (the SDK's 8-bit mode, sun or
// glass noise) and I as the intensity; kIntensity10 reads them as intensity bits 8-9 (the SDK's
// default 10-bit mode). Either way the distance is (Si & 0xFFFC) / 4 mm.
enum class SampleFormat : std::uint8_t { kDistance, kIntensity8, kIntensity10 };

std::size_t sample_bytes(SampleFormat format);

// A sample as it goes on the wire.
struct RawSample {
  std::uint16_t distance_raw = 0;  // Si
  std::uint8_t intensity_raw = 0;  // I, sent only by the intensity formats
};

// CS: the 16-bit XOR of PH, FSA, every sample (on the intensity formats the byte I as a word of
// its own, then Si), the word CT | LSN << 8, and LSA. `packet` is a whole packet from PH on; its
// CS field takes no part. 0 when `packet` is shorter than the LSN it holds.
std::uint16_t scan_checksum(std::span<const std::uint8_t> packet, SampleFormat format);

// A whole packet, CS included (computed, then xor-ed with `checksum_xor` so that a device model can
// send a wrong one). LSN is samples.size(), which must lie in 1..kMaxSamplesPerPacket.
std::vector<std::uint8_t> encode_scan_packet(std::uint8_t ct, std::uint16_t first_angle_raw,
                                             std::uint16_t last_angle_raw,
                                             std::span<const RawSample> samples,
                                             SampleFormat format, std::uint16_t checksum_xor = 0);

// FSA/LSA <-> degrees: raw = (round(deg * 64) mod 360 * 64) << 1 | 1 (bit 0 is the check bit, 1).
std::uint16_t angle_raw_from_deg(double angle_deg);
double angle_deg_from_raw(std::uint16_t angle_raw);
// The triangulation correction of the G4 manual, added to the interpolated angle of a sample:
// atan(21.8 * (155.3 - d) / (155.3 * d)) in degrees for a distance d > 0 mm, 0 for d = 0 (no
// return). It is 0 at 155.3 mm and tends to -8.0 degrees far away.
double angle_correction_deg(double distance_mm);
// Si -> millimetres for the format (Si / 4; the intensity formats drop Si's low two bits first).
double distance_mm_from_raw(std::uint16_t distance_raw, SampleFormat format);

// One measurement in the lidar's own polar frame: the G4 counts angles clockwise, seen from above,
// from its zero at the exit of its cable.
struct Sample {
  double angle_deg = 0.0;  // corrected, in [0, 360)
  double range_m = 0.0;    // 0: no return
  std::uint16_t intensity = 0;
};

struct ScanPacket {
  std::uint8_t ct = 0;
  std::uint16_t first_angle_raw = 0;  // FSA
  std::uint16_t last_angle_raw = 0;   // LSA
  std::uint16_t checksum = 0;         // CS, as sent and found right
  std::vector<Sample> samples;        // LSN of them

  bool starts_scan() const { return (ct & 0x01) != 0; }
  // A zero packet's CT >> 1 is the frequency of the turn that just ended in 1/10 Hz, on firmware
  // that reports it (0 otherwise: nullopt). Other packets' upper CT bits are not a frequency.
  std::optional<double> scan_frequency_hz() const;
};

// Decodes a whole packet whose checksum has been found right: the angles interpolated from FSA to
// LSA (LSA below FSA means the packet crosses 360), corrected, and wrapped into [0, 360).
// nullopt when `packet` is not one whole well-formed packet of the format.
std::optional<ScanPacket> decode_scan_packet(std::span<const std::uint8_t> packet,
                                             SampleFormat format);

}  // namespace mobot::protocol::ydlidar
