#include "tools/emulate/devices/ydlidar_g4_device.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "drivers/protocol/ydlidar_scan.h"

namespace mobot::emulate {
namespace {

namespace yd = protocol::ydlidar;

constexpr double kMinScanRate_hz = 5.0;
constexpr double kMaxScanRate_hz = 12.0;
// The distance word holds Si = 4 * mm in 16 bits.
constexpr double kMaxWireRange_m = 65535.0 / 4000.0;
constexpr int kBitsPerByte = 10;  // start, 8 data, stop
// A turn adds a zero packet and ends one packet short: two headers beyond the full packets.
constexpr double kExtraPacketsPerTurn = 2.0;
// The fixed-point search for the direction a sample looked in (its correction depends on the
// distance it finds there) settles in two or three steps away from edges.
constexpr int kDirectionIterations = 3;

bool is_command(std::uint8_t byte, yd::Command command) {
  return byte == static_cast<std::uint8_t>(command);
}

double frequency_step_hz(yd::Command command) {
  switch (command) {
    case yd::Command::kScanFrequencyUp0p1:
      return 0.1;
    case yd::Command::kScanFrequencyDown0p1:
      return -0.1;
    case yd::Command::kScanFrequencyUp1:
      return 1.0;
    case yd::Command::kScanFrequencyDown1:
      return -1.0;
    default:
      return 0.0;
  }
}

}  // namespace

YdlidarG4Device::YdlidarG4Device(const EmulatedWorld& world, Options options)
    : world_(world), options_(std::move(options)), rng_(options_.seed) {
  const Options& o = options_;
  if (!geometry::is_finite(o.mounting_pose) || !std::isfinite(o.height_m)) {
    throw std::invalid_argument("ydlidar g4: the mounting pose and height must be finite");
  }
  if (!(o.scan_rate_hz >= kMinScanRate_hz && o.scan_rate_hz <= kMaxScanRate_hz)) {
    throw std::invalid_argument("ydlidar g4: the scan rate must lie in 5..12 Hz");
  }
  if (!yd::sampling_rate_code(o.sampling_rate_hz)) {
    throw std::invalid_argument("ydlidar g4: the sampling rate must be 4000, 8000 or 9000 Hz");
  }
  if (o.samples_per_packet < 1 || o.samples_per_packet > yd::kMaxSamplesPerPacket) {
    throw std::invalid_argument("ydlidar g4: 1..80 samples per packet");
  }
  if (!(o.min_range_m >= 0.0 && o.min_range_m < o.max_range_m &&
        o.max_range_m <= kMaxWireRange_m)) {
    throw std::invalid_argument("ydlidar g4: 0 <= min range < max range <= 16.38 m");
  }
  if (o.baud_rate <= 0) throw std::invalid_argument("ydlidar g4: the baud rate must be positive");
  const double packets_per_s = o.sampling_rate_hz / static_cast<double>(o.samples_per_packet) +
                               kExtraPacketsPerTurn * kMaxScanRate_hz;
  const double bytes_per_s = o.sampling_rate_hz * static_cast<double>(yd::sample_bytes(o.format)) +
                             packets_per_s * static_cast<double>(yd::kScanHeaderBytes);
  const double line_bytes_per_s = o.baud_rate / static_cast<double>(kBitsPerByte);
  if (bytes_per_s > line_bytes_per_s) {
    throw std::invalid_argument("ydlidar g4: the scan data would not fit the serial line");
  }
  byte_time_s_ = 1.0 / line_bytes_per_s;
  scan_rate_hz_ = o.scan_rate_hz;
}

void YdlidarG4Device::receive(std::span<const std::uint8_t> bytes, double now_s) {
  advance(now_s);
  for (const std::uint8_t byte : bytes) {
    if (!pending_sync_) {
      pending_sync_ = byte == yd::kCommandSync;
    } else if (byte != yd::kCommandSync) {
      pending_sync_ = false;
      handle(byte, now_s_);
    }
  }
}

std::vector<std::uint8_t> YdlidarG4Device::transmit(double now_s) {
  advance(now_s);
  transmitted_bytes_ += outbox_.size();
  return std::exchange(outbox_, {});
}

void YdlidarG4Device::advance(double now_s) {
  if (std::isfinite(now_s)) now_s_ = std::max(now_s_, now_s);
  if (scanning_) take_samples(now_s_);
  send_line(now_s_);
}

void YdlidarG4Device::take_samples(double now_s) {
  const double sample_period_s = 1.0 / options_.sampling_rate_hz;
  const double turns_per_sample = scan_rate_hz_ * sample_period_s;
  while (true) {
    const auto k = static_cast<double>(next_sample_);
    const double sample_s = scan_start_s_ + k * sample_period_s;
    if (sample_s > now_s) break;
    const double turns = k * turns_per_sample;
    // The previous sample's turns computed as it was then, so that no turn is seen twice.
    const bool starts_turn =
        next_sample_ == 0 ||
        std::floor(turns) != std::floor(static_cast<double>(next_sample_ - 1) * turns_per_sample);
    const double raw_deg = (turns - std::floor(turns)) * 360.0;
    if (starts_turn) close_packet();
    if (packet_.empty()) packet_first_deg_ = raw_deg;
    packet_.push_back(measure(raw_deg));
    packet_last_deg_ = raw_deg;
    packet_ready_s_ = sample_s;
    packet_is_zero_ = starts_turn;
    if (starts_turn || packet_.size() >= options_.samples_per_packet) close_packet();
    ++next_sample_;
  }
}

void YdlidarG4Device::close_packet() {
  if (packet_.empty()) return;
  std::uint8_t ct = 0;
  if (packet_is_zero_) {
    const long tenths_hz = std::clamp(std::lround(scan_rate_hz_ * 10.0), 0L, 127L);
    ct = static_cast<std::uint8_t>(0x01 | tenths_hz << 1);
  }
  Frame frame;
  frame.ready_s = packet_ready_s_;
  frame.bytes = yd::encode_scan_packet(ct, yd::angle_raw_from_deg(packet_first_deg_),
                                       yd::angle_raw_from_deg(packet_last_deg_), packet_,
                                       options_.format, bad_checksums_ ? 0xFFFF : 0x0000);
  frame.scan_data = true;
  frame.ends_turn = packet_is_zero_ && turn_open_;
  if (packet_is_zero_) turn_open_ = true;
  line_.push_back(std::move(frame));
  packet_.clear();
  packet_is_zero_ = false;
}

double YdlidarG4Device::cast_mm(const geometry::Pose2D& lidar, double angle_deg) const {
  const std::optional<double> hit_m =
      world_.cast_ray({lidar.x, lidar.y}, lidar.theta + yd::sensor_angle_rad(angle_deg),
                      options_.height_m, options_.max_range_m);
  return hit_m ? *hit_m * 1000.0 : 0.0;
}

yd::RawSample YdlidarG4Device::measure(double raw_angle_deg) {
  const geometry::Pose2D lidar = geometry::compose(world_.base_pose(), options_.mounting_pose);
  // The host adds the correction of the distance it reads to the raw angle, so the sample must
  // be what lies along raw + correction(that distance).
  double distance_mm = last_distance_mm_;
  for (int i = 0; i < kDirectionIterations; ++i) {
    distance_mm = cast_mm(lidar, raw_angle_deg + yd::angle_correction_deg(distance_mm));
  }
  last_distance_mm_ = distance_mm;
  yd::RawSample sample;
  if (!(distance_mm > 0.0)) return sample;
  // At an edge (a near wall on one side of it, nothing on the other) the search can swing
  // between the two: a distance whose own direction does not see it would be placed where
  // nothing is. The head gets no clean return there either: drop it.
  const double check_mm = cast_mm(lidar, raw_angle_deg + yd::angle_correction_deg(distance_mm));
  if (std::abs(check_mm - distance_mm) > 0.02 * distance_mm + 10.0) return sample;
  const double hit_m = distance_mm / 1000.0;
  const double sigma_m = std::max(0.01, 0.005 * hit_m);
  const double range_m = hit_m + std::normal_distribution<double>(0.0, sigma_m)(rng_);
  if (range_m < options_.min_range_m || range_m > options_.max_range_m) return sample;
  if (options_.format == yd::SampleFormat::kDistance) {
    sample.distance_raw = static_cast<std::uint16_t>(std::lround(range_m * 4000.0));
  } else {
    // Whole millimetres: Si's low two bits are the intensity's, left 0 here.
    sample.distance_raw = static_cast<std::uint16_t>(std::lround(range_m * 1000.0) * 4);
    // Weaker returns from farther away; the G4 reports no unit for it.
    sample.intensity_raw = static_cast<std::uint8_t>(std::lround(255.0 / (1.0 + range_m)));
  }
  return sample;
}

void YdlidarG4Device::send_line(double now_s) {
  while (!line_.empty()) {
    Frame& frame = line_.front();
    const double start_s = std::max(line_free_s_, frame.ready_s);
    // A byte is out once its stop bit is; the epsilon keeps whole byte times whole.
    const double fit = std::floor((now_s - start_s) / byte_time_s_ + 1e-9);
    if (fit < 1.0) break;
    const std::size_t left = frame.bytes.size() - frame.sent;
    const std::size_t count = std::min(left, static_cast<std::size_t>(std::min(fit, 1e9)));
    const auto begin = frame.bytes.begin() + static_cast<std::ptrdiff_t>(frame.sent);
    outbox_.insert(outbox_.end(), begin, begin + static_cast<std::ptrdiff_t>(count));
    frame.sent += count;
    line_free_s_ = start_s + static_cast<double>(count) * byte_time_s_;
    if (frame.sent < frame.bytes.size()) break;
    if (frame.ends_turn && turn_end_hook_) turn_end_hook_(transmitted_bytes_ + outbox_.size());
    line_.pop_front();
  }
}

void YdlidarG4Device::handle(std::uint8_t command, double now_s) {
  const bool stop =
      is_command(command, yd::Command::kStopScan) || is_command(command, yd::Command::kForceStop);
  const bool restart =
      is_command(command, yd::Command::kRestart) || is_command(command, yd::Command::kRestartSdk);
  if (restart) {
    stop_scan();
    return;
  }
  if (scanning_) {
    if (stop) stop_scan();
    return;
  }
  switch (static_cast<yd::Command>(command)) {
    case yd::Command::kStartScan:
    case yd::Command::kForceScan:
      start_scan(now_s);
      break;
    case yd::Command::kGetDeviceInfo:
      queue_response({yd::kDeviceInfoBytes, yd::ResponseMode::kSingle, yd::kTypeDeviceInfo},
                     yd::encode_device_info(options_.info), now_s);
      break;
    case yd::Command::kGetHealth:
    case yd::Command::kGetHealthManual:
      queue_response({yd::kHealthBytes, yd::ResponseMode::kSingle, yd::kTypeHealth},
                     yd::encode_health(options_.health), now_s);
      break;
    case yd::Command::kScanFrequencyUp0p1:
    case yd::Command::kScanFrequencyDown0p1:
    case yd::Command::kScanFrequencyUp1:
    case yd::Command::kScanFrequencyDown1: {
      const double step_hz = frequency_step_hz(static_cast<yd::Command>(command));
      // In hundredths, as the device keeps it, so that steps do not drift.
      scan_rate_hz_ = std::clamp(std::round((scan_rate_hz_ + step_hz) * 100.0) / 100.0,
                                 kMinScanRate_hz, kMaxScanRate_hz);
      queue_scan_frequency(now_s);
      break;
    }
    case yd::Command::kGetScanFrequency:
      queue_scan_frequency(now_s);
      break;
    case yd::Command::kGetSamplingRate: {
      const std::uint8_t code = yd::sampling_rate_code(options_.sampling_rate_hz).value_or(2);
      queue_response({yd::kSamplingRateBytes, yd::ResponseMode::kSingle, yd::kTypeDeviceInfo},
                     std::span<const std::uint8_t>(&code, 1), now_s);
      break;
    }
    default:
      break;  // stop while idle, or a code the G4 does not know: no answer
  }
}

void YdlidarG4Device::start_scan(double now_s) {
  queue_response({yd::kStartScanResponseLength, yd::ResponseMode::kContinuous, yd::kTypeScan}, {},
                 now_s);
  scanning_ = true;
  scan_start_s_ = now_s;
  next_sample_ = 0;
  packet_.clear();
  packet_is_zero_ = false;
  turn_open_ = false;
}

void YdlidarG4Device::stop_scan() {
  scanning_ = false;
  packet_.clear();
  packet_is_zero_ = false;
  turn_open_ = false;
  // Packets the line has begun go out whole; the rest never leave the device.
  std::erase_if(line_, [](const Frame& frame) { return frame.scan_data && frame.sent == 0; });
}

void YdlidarG4Device::queue_response(const yd::ResponseHeader& header,
                                     std::span<const std::uint8_t> payload, double now_s) {
  Frame frame;
  frame.ready_s = now_s;
  const auto head = yd::encode_response_header(header);
  frame.bytes.assign(head.begin(), head.end());
  frame.bytes.insert(frame.bytes.end(), payload.begin(), payload.end());
  line_.push_back(std::move(frame));
}

void YdlidarG4Device::queue_scan_frequency(double now_s) {
  const auto hundredths = static_cast<std::uint32_t>(std::lround(scan_rate_hz_ * 100.0));
  const std::uint8_t payload[yd::kScanFrequencyBytes] = {
      static_cast<std::uint8_t>(hundredths & 0xFF),
      static_cast<std::uint8_t>(hundredths >> 8 & 0xFF),
      static_cast<std::uint8_t>(hundredths >> 16 & 0xFF),
      static_cast<std::uint8_t>(hundredths >> 24)};
  queue_response({yd::kScanFrequencyBytes, yd::ResponseMode::kSingle, yd::kTypeDeviceInfo}, payload,
                 now_s);
}

}  // namespace mobot::emulate
