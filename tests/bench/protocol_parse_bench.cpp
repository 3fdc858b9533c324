// Host-side parse throughput of every serial protocol mobot speaks, on byte streams the device
// emulators (tools/emulate/devices) produce, fed in the chunk sizes a serial read returns. Each
// benchmark reports bytes_per_second (Google Benchmark's M is 2^20 bytes) and x_line: how many
// times the device's own line rate (8N1, 10 bits a byte) the parser keeps up with on one core
// (printed as a rate, ".../s", because it is bytes over line bytes per second of CPU time).
//   cmake --build build --target mobot_bench && build/tests/bench/mobot_bench
//     --benchmark_filter='YdlidarG4|Sick|MotionMind|Arduino|Modbus'
// or standalone:
//   g++ -std=c++20 -O2 -g -DNDEBUG -I. tests/bench/protocol_parse_bench.cpp drivers/protocol/*.cpp
//     core/geometry/pose2d.cpp tools/emulate/devices/{ydlidar_g4,sick_lms2xx,motion_mind,
//     dashgo_base,modbus_sensor_bus}_device.cpp -lbenchmark -lbenchmark_main -lpthread

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "drivers/protocol/line_framer.h"
#include "drivers/protocol/motion_mind.h"
#include "drivers/protocol/ros_arduino_bridge.h"
#include "drivers/protocol/sick_lms2xx_scan.h"
#include "drivers/protocol/sick_lms2xx_telegram.h"
#include "drivers/protocol/ydlidar_g4.h"
#include "drivers/protocol/ydlidar_scan.h"
#include "drivers/protocol/ydlidar_stream_parser.h"
#include "tools/emulate/devices/dashgo_base_device.h"
#include "tools/emulate/devices/modbus_sensor_bus_device.h"
#include "tools/emulate/devices/motion_mind_device.h"
#include "tools/emulate/devices/sick_lms2xx_device.h"
#include "tools/emulate/devices/ydlidar_g4_device.h"

namespace mobot::emulate {
namespace {

namespace yd = protocol::ydlidar;
namespace sick = protocol::sick;
namespace mm = protocol::motion_mind;
namespace bridge = protocol::arduino_bridge;

using Bytes = std::vector<std::uint8_t>;

constexpr double kBitsPerByte = 10.0;  // 8N1
// The emulator's own grain (tools/emulate/main.cpp steps every device once a millisecond).
constexpr double kStep_s = 0.001;

double line_bytes_per_s(int baud) { return baud / kBitsPerByte; }

// A 10 x 6 m room with a round pillar: ranges from 0.3 to 9 m, so the lidars' samples vary as in
// an office rather than repeating one distance.
class Room final : public EmulatedWorld {
 public:
  geometry::Pose2D base_pose() const override { return pose_; }
  void set_base_pose(const geometry::Pose2D& pose) override { pose_ = pose; }

  std::optional<double> cast_ray(geometry::Point2D from, double angle_rad, double /*height_m*/,
                                 double max_range_m) const override {
    const double dx = std::cos(angle_rad);
    const double dy = std::sin(angle_rad);
    double hit_m = std::numeric_limits<double>::infinity();
    if (dx > 1e-12) hit_m = std::min(hit_m, (kWidth_m - from.x) / dx);
    if (dx < -1e-12) hit_m = std::min(hit_m, -from.x / dx);
    if (dy > 1e-12) hit_m = std::min(hit_m, (kDepth_m - from.y) / dy);
    if (dy < -1e-12) hit_m = std::min(hit_m, -from.y / dy);
    // The pillar: |from + t d - c| = r, the nearer root in front.
    const double px = from.x - kPillarX_m;
    const double py = from.y - kPillarY_m;
    const double b = px * dx + py * dy;
    const double disc = b * b - (px * px + py * py - kPillarRadius_m * kPillarRadius_m);
    if (disc >= 0.0 && -b - std::sqrt(disc) > 0.0) hit_m = std::min(hit_m, -b - std::sqrt(disc));
    if (!(hit_m <= max_range_m)) return std::nullopt;
    return hit_m;
  }

 private:
  static constexpr double kWidth_m = 10.0;
  static constexpr double kDepth_m = 6.0;
  static constexpr double kPillarX_m = 6.5;
  static constexpr double kPillarY_m = 3.5;
  static constexpr double kPillarRadius_m = 0.4;
  geometry::Pose2D pose_{3.2, 2.1, 0.4};
};

// Feeds `stream` to `parse` in reads of at most `chunk_bytes`.
template <typename Parse>
void feed_in_chunks(const Bytes& stream, std::size_t chunk_bytes, Parse&& parse) {
  for (std::size_t at = 0; at < stream.size(); at += chunk_bytes) {
    parse(std::span<const std::uint8_t>(stream).subspan(at,
                                                        std::min(chunk_bytes, stream.size() - at)));
  }
}

void report(benchmark::State& state, std::size_t stream_bytes, int baud, const char* name) {
  const auto bytes = static_cast<double>(state.iterations()) * static_cast<double>(stream_bytes);
  state.SetBytesProcessed(static_cast<std::int64_t>(bytes));
  state.counters[name] =
      benchmark::Counter(bytes / line_bytes_per_s(baud), benchmark::Counter::kIsRate);
}

// ---- YDLIDAR G4: 230400 baud, 9000 samples/s at 7 Hz, 40 samples a packet ----

constexpr double kG4Stream_s = 10.0;

const Bytes& g4_stream() {
  static const Bytes stream = [] {
    Room room;
    YdlidarG4Device::Options options;
    options.mounting_pose = {0.05, 0.0, 0.0};
    YdlidarG4Device device(room, options);
    device.receive(yd::encode_command(yd::Command::kStartScan), 0.0);
    Bytes out;
    for (double t_s = kStep_s; t_s <= kG4Stream_s; t_s += kStep_s) {
      const Bytes sent = device.transmit(t_s);
      out.insert(out.end(), sent.begin(), sent.end());
    }
    return out;
  }();
  return stream;
}

// What YdlidarG4Laser's session does with each read: parse, assemble turns, convert each turn.
void BM_YdlidarG4(benchmark::State& state) {
  const Bytes& stream = g4_stream();
  const auto chunk_bytes = static_cast<std::size_t>(state.range(0));
  const yd::LaserScanOptions scan_options;
  std::vector<yd::StreamItem> items;
  std::uint64_t turns = 0;
  std::uint64_t checksum_errors = 0;
  for (auto _ : state) {
    yd::StreamParser parser;
    yd::ScanAssembler assembler;
    feed_in_chunks(stream, chunk_bytes, [&](std::span<const std::uint8_t> chunk) {
      parser.feed(chunk, items);
      for (const yd::StreamItem& item : items) {
        const auto* packet = std::get_if<yd::ScanPacket>(&item);
        if (packet == nullptr) continue;
        if (std::optional<yd::Scan> turn = assembler.add(*packet)) {
          const msgs::LaserScan scan = yd::to_laser_scan(*turn, scan_options, 0.0);
          benchmark::DoNotOptimize(scan.ranges_m.data());
          ++turns;
        }
      }
      items.clear();
    });
    checksum_errors += parser.stats().checksum_errors;
  }
  if (checksum_errors > 0) state.SkipWithError("the G4 stream failed its checksums");
  report(state, stream.size(), yd::kBaudRate, "x_line");
  state.counters["turns"] = static_cast<double>(turns) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_YdlidarG4)->Arg(64)->Arg(4096)->Unit(benchmark::kMicrosecond);

// The stream parser alone (packets found, checksummed, samples decoded with their angle
// correction): the share of BM_YdlidarG4 that is not turn assembly and binning.
void BM_YdlidarG4ParserOnly(benchmark::State& state) {
  const Bytes& stream = g4_stream();
  const auto chunk_bytes = static_cast<std::size_t>(state.range(0));
  std::vector<yd::StreamItem> items;
  for (auto _ : state) {
    yd::StreamParser parser;
    feed_in_chunks(stream, chunk_bytes, [&](std::span<const std::uint8_t> chunk) {
      parser.feed(chunk, items);
      benchmark::DoNotOptimize(items.data());
      items.clear();
    });
  }
  report(state, stream.size(), yd::kBaudRate, "x_line");
}
BENCHMARK(BM_YdlidarG4ParserOnly)->Arg(4096)->Unit(benchmark::kMicrosecond);

// ---- SICK LMS2xx: 180 deg at 0.5 deg (361 values, 734-byte telegrams) streaming in mode 0x24 ----

constexpr double kSickStream_s = 4.0;
constexpr int kSickSlowBaud = 38400;
constexpr int kSickFastBaud = 500000;

// Streamed at 500000 baud, 37.5 scans/s. At 38400 the LMS sends the same telegrams, only every
// 8th of them, so one stream serves both rates.
const Bytes& sick_stream() {
  static const Bytes stream = [] {
    Room room;
    SickLms2xxDevice::Options options;
    options.initial_baud = kSickFastBaud;
    options.initial_mode = sick::OperatingMode::kContinuousAllValues;
    options.initial_variant = {sick::ScanAngle::k180Deg, sick::AngularResolution::kHalfDeg};
    SickLms2xxDevice device(room, options);
    Bytes out;
    for (double t_s = kStep_s; t_s <= kSickStream_s; t_s += kStep_s) {
      const Bytes sent = device.transmit(t_s);
      out.insert(out.end(), sent.begin(), sent.end());
    }
    return out;
  }();
  return stream;
}

// What SickLms2xxLaser does with each read in mode 0x24: find telegrams, decode B0, convert.
void BM_SickLms2xx(benchmark::State& state) {
  const Bytes& stream = sick_stream();
  const auto chunk_bytes = static_cast<std::size_t>(state.range(0));
  sick::LaserScanOptions scan_options;
  scan_options.range_bits = sick::range_bits_for_measuring_mode(0x00);
  std::uint64_t scans = 0;
  std::uint64_t crc_errors = 0;
  for (auto _ : state) {
    sick::TelegramStream telegrams(sick::StreamDirection::kFromLms);
    feed_in_chunks(stream, chunk_bytes, [&](std::span<const std::uint8_t> chunk) {
      for (const sick::StreamEvent& event : telegrams.feed(chunk)) {
        if (event.kind != sick::StreamEvent::Kind::kTelegram) continue;
        const std::optional<sick::MeasuredValues> values =
            sick::decode_measured_values(event.telegram);
        if (!values) continue;
        const std::optional<msgs::LaserScan> scan = sick::to_laser_scan(*values, scan_options);
        if (scan) {
          benchmark::DoNotOptimize(scan->ranges_m.data());
          ++scans;
        }
      }
    });
    crc_errors += telegrams.stats().crc_errors;
  }
  if (crc_errors > 0) state.SkipWithError("the SICK stream failed its CRCs");
  report(state, stream.size(), kSickSlowBaud, "x_line_38400");
  report(state, stream.size(), kSickFastBaud, "x_line_500000");
  state.counters["scans"] = static_cast<double>(scans) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_SickLms2xx)->Arg(64)->Arg(4096)->Unit(benchmark::kMicrosecond);

// ---- Motion Mind 3: 19200 baud, two wheel boards answering MOVEAT_VELOCITY with POSITION ----

struct MotionMindExchange {
  mm::ExpectedReply expected;
  Bytes reply;
  std::optional<mm::RegisterMask> read_mask;  // a READ's; nothing for a motion command or a write
};

constexpr int kMotionMindTicks = 2000;  // 40 s of the 50 Hz wheel loop
constexpr std::uint8_t kLeftBoard = 1;
constexpr std::uint8_t kRightBoard = 2;

// The replies as the bus model sends them to what R1's wheel line asks: the set-up writes (ACK),
// then per tick a velocity command to each board (POSITION back) and, every 5th tick, a read of
// position and status. A host reads one reply per command, so each is kept apart.
const std::vector<MotionMindExchange>& motion_mind_exchanges() {
  static const std::vector<MotionMindExchange> exchanges = [] {
    MotionMindBusOptions options;
    for (const std::uint8_t address : {kLeftBoard, kRightBoard}) {
      MotionMindBoardOptions board;
      board.address = address;
      options.boards.push_back(board);
    }
    MotionMindBus bus(options);
    std::vector<MotionMindExchange> out;
    double t_s = 0.0;
    auto ask = [&](const mm::Packet& command, const mm::ExpectedReply& expected,
                   std::optional<mm::RegisterMask> read_mask = std::nullopt) {
      bus.receive(command, t_s);
      t_s += mm::max_round_trip_s(command.size(), mm::reply_bytes(expected), options.baud);
      out.push_back({expected, bus.transmit(t_s), read_mask});
    };
    const mm::BoardSetup setup = mm::r1_wheel_setup();
    for (const std::uint8_t address : {kLeftBoard, kRightBoard}) {
      for (const mm::Exchange& exchange : mm::setup_exchanges(address, setup)) {
        ask(exchange.command, exchange.reply);
      }
    }
    const mm::RegisterMask seek_mask =
        mm::mask_of(mm::Register::kPosition) | mm::mask_of(mm::Register::kStatus);
    for (int tick = 0; tick < kMotionMindTicks; ++tick) {
      // A slow sweep of speeds so the positions grow and change sign.
      const int speed = static_cast<int>(std::lround(300.0 * std::sin(tick * 0.01)));
      ask(mm::move_at_velocity(kLeftBoard, speed), mm::motion_reply(kLeftBoard, setup.function));
      ask(mm::move_at_velocity(kRightBoard, -speed), mm::motion_reply(kRightBoard, setup.function));
      if (tick % 5 == 0) {
        ask(mm::read_registers(kLeftBoard, seek_mask), mm::read_reply(kLeftBoard, seek_mask),
            seek_mask);
      }
    }
    return out;
  }();
  return exchanges;
}

// ReplyParser armed before each command, as MotionMindLine does, fed the reply in reads of at most
// `chunk` bytes (a reply is 1-9 bytes: 64 means one read per reply, 1 a read per byte).
void BM_MotionMindReplies(benchmark::State& state) {
  const std::vector<MotionMindExchange>& exchanges = motion_mind_exchanges();
  const auto chunk_bytes = static_cast<std::size_t>(state.range(0));
  std::size_t stream_bytes = 0;
  for (const MotionMindExchange& exchange : exchanges) stream_bytes += exchange.reply.size();
  std::uint64_t replies = 0;
  std::uint64_t positions = 0;
  for (auto _ : state) {
    mm::ReplyParser parser;
    for (const MotionMindExchange& exchange : exchanges) {
      parser.expect(exchange.expected);
      feed_in_chunks(exchange.reply, chunk_bytes, [&](std::span<const std::uint8_t> chunk) {
        const std::optional<mm::Reply> reply = parser.feed(chunk);
        if (!reply) return;
        ++replies;
        if (reply->ack) return;
        std::optional<std::int64_t> position_counts;
        if (exchange.read_mask) {
          position_counts =
              mm::register_value(*exchange.read_mask, mm::Register::kPosition, reply->data);
        } else if (const std::optional<mm::MotionFeedback> feedback =
                       mm::decode_motion_reply(mm::function_bit::kRetPos, reply->data)) {
          position_counts = feedback->position_counts;
        }
        if (position_counts) {
          benchmark::DoNotOptimize(*position_counts);
          ++positions;
        }
      });
    }
  }
  if (replies != exchanges.size() * state.iterations()) {
    state.SkipWithError("a Motion Mind reply was lost");
  }
  report(state, stream_bytes, mm::kDefaultBaud, "x_line");
  state.counters["replies"] = static_cast<double>(exchanges.size());
  state.counters["positions"] =
      static_cast<double>(positions) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_MotionMindReplies)->Arg(1)->Arg(64)->Unit(benchmark::kMicrosecond);

// ---- ROSArduinoBridge (Dashgo D1 base): 115200 baud, CR LF lines ----

constexpr int kArduinoCycles = 3000;  // 60 s of DashgoBoard's 50 Hz cycle
constexpr int kArduinoBaud = 115200;

struct ArduinoReplies {
  Bytes stream;
  // Integers each reply holds, in order; 0 for "OK".
  std::vector<std::size_t> integers;
};

// DashgoBoard's cycle against the base model: "m L R" (OK) and "e" (two encoder counts) every
// cycle, "p" (four sonars) and "j" every 5th, "v" every 50th. The wheels turn in place, so the
// encoder counts run through five digits and wrap, as on the robot.
const ArduinoReplies& arduino_replies() {
  static const ArduinoReplies replies = [] {
    Room room;
    DashgoBaseDeviceOptions options;
    options.sonars_in_base = {
        {0.18, 0.0, 0.0}, {0.1, 0.15, 1.0}, {0.1, -0.15, -1.0}, {-0.18, 0.0, 3.14}};
    DashgoBaseDevice base(options, room);
    ArduinoReplies out;
    double t_s = 0.0;
    auto ask = [&](const std::string& command, std::size_t integers) {
      base.receive(std::span(reinterpret_cast<const std::uint8_t*>(command.data()), command.size()),
                   t_s);
      // Well past the reply delay and the reply's bytes on the wire.
      t_s += 0.004;
      const Bytes reply = base.transmit(t_s);
      out.stream.insert(out.stream.end(), reply.begin(), reply.end());
      out.integers.push_back(integers);
    };
    for (int cycle = 0; cycle < kArduinoCycles; ++cycle) {
      ask(bridge::motor_speeds_command(600, -600), 0);
      ask(bridge::command(bridge::kReadEncoders), 2);
      if (cycle % 5 == 0) {
        ask(bridge::command(bridge::kReadSonars), options.sonars_in_base.size());
        ask(bridge::command(bridge::kReadEstopButton), 1);
      }
      if (cycle % 50 == 0) ask(bridge::command(bridge::kReadBattery), 1);
    }
    return out;
  }();
  return replies;
}

// ArduinoLink's reading: the line framer, then each line as "OK" or its integers, the encoder
// counts unwrapped.
void BM_ArduinoBridgeReplies(benchmark::State& state) {
  const ArduinoReplies& replies = arduino_replies();
  const auto chunk_bytes = static_cast<std::size_t>(state.range(0));
  std::vector<std::string> lines;
  std::uint64_t parsed = 0;
  for (auto _ : state) {
    protocol::LineFramer framer;
    bridge::EncoderUnwrap left;
    bridge::EncoderUnwrap right;
    std::size_t next = 0;
    feed_in_chunks(replies.stream, chunk_bytes, [&](std::span<const std::uint8_t> chunk) {
      framer.feed(chunk, lines);
      for (const std::string& line : lines) {
        const std::size_t integers = replies.integers[next++];
        if (integers == 0) {
          parsed += bridge::is_ok(line) ? 1 : 0;
          continue;
        }
        const std::optional<std::vector<long>> values = bridge::parse_integers(line, integers);
        if (!values) continue;
        ++parsed;
        if (integers == 2) {
          benchmark::DoNotOptimize(left.update((*values)[0]));
          benchmark::DoNotOptimize(right.update((*values)[1]));
        }
      }
      lines.clear();
    });
  }
  if (parsed != replies.integers.size() * state.iterations()) {
    state.SkipWithError("an Arduino reply did not parse");
  }
  report(state, replies.stream.size(), kArduinoBaud, "x_line");
  state.counters["lines"] = static_cast<double>(replies.integers.size());
}
BENCHMARK(BM_ArduinoBridgeReplies)->Arg(64)->Arg(4096)->Unit(benchmark::kMicrosecond);

// ---- Modbus RTU (R1's sensor bus), the emulator's request framer: 115200 baud ----

constexpr int kModbusCycles = 1000;  // 100 s of the poll schedule's 10 Hz round
constexpr int kModbusBaud = 115200;

Bytes read_request(int node, std::uint8_t function) {
  Bytes frame = {static_cast<std::uint8_t>(node), function, 0, 0, 0, 1};
  const std::uint16_t crc = modbus_crc16(frame);
  frame.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  frame.push_back(static_cast<std::uint8_t>(crc >> 8));
  return frame;
}

// The master's requests of one poll round as ModbusPollSchedule spreads them: the compass and the
// eight sonars at 10 Hz (input register 0), the limit switch at 20 Hz (discrete input 0).
const Bytes& modbus_requests() {
  static const Bytes stream = [] {
    constexpr std::uint8_t kReadDiscreteInputs = 0x02;
    constexpr std::uint8_t kReadInputRegisters = 0x04;
    const ModbusSensorBusOptions options;
    Bytes out;
    auto add = [&out](const Bytes& frame) { out.insert(out.end(), frame.begin(), frame.end()); };
    for (int cycle = 0; cycle < kModbusCycles; ++cycle) {
      add(read_request(options.compass_node, kReadInputRegisters));
      add(read_request(options.limit_switch_node, kReadDiscreteInputs));
      for (const int node : options.sonar_nodes) add(read_request(node, kReadInputRegisters));
      add(read_request(options.limit_switch_node, kReadDiscreteInputs));
    }
    return out;
  }();
  return stream;
}

void BM_ModbusRequestFramer(benchmark::State& state) {
  const Bytes& stream = modbus_requests();
  const auto chunk_bytes = static_cast<std::size_t>(state.range(0));
  std::uint64_t requests = 0;
  for (auto _ : state) {
    ModbusRtuRequestFramer framer;
    feed_in_chunks(stream, chunk_bytes, [&](std::span<const std::uint8_t> chunk) {
      const std::vector<Bytes> frames = framer.push(chunk);
      requests += frames.size();
      benchmark::DoNotOptimize(frames.data());
    });
  }
  const std::size_t per_pass = static_cast<std::size_t>(kModbusCycles) * 11;
  if (requests != per_pass * state.iterations()) state.SkipWithError("a request was not framed");
  report(state, stream.size(), kModbusBaud, "x_line");
  state.counters["requests"] = static_cast<double>(per_pass);
}
// 8: one request per read, as a slave sees them between the master's pauses.
BENCHMARK(BM_ModbusRequestFramer)->Arg(8)->Arg(64)->Arg(4096)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace mobot::emulate
