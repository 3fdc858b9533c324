#include "drivers/hardware/ydlidar_g4_laser.h"

#include <array>
#include <variant>

#include <spdlog/spdlog.h>

namespace mobot::drivers::hardware {

namespace ydlidar = protocol::ydlidar;
using Clock = std::chrono::steady_clock;

// One connection's conversation with the head: the parser and assembler live as long as the
// line is open, so a reconnect starts from a clean stream.
class YdlidarG4Laser::Session {
 public:
  Session(YdlidarG4Laser& laser, serial::SerialPort& port)
      : laser_(laser), port_(port), parser_({laser.options_.format}) {}

  void send(ydlidar::Command command) {
    const auto bytes = ydlidar::encode_command(command);
    port_.write_all(std::span<const std::uint8_t>(bytes), std::chrono::milliseconds(100));
  }

  // The single response of `type` to the command just sent, or DeviceFault("silent").
  ydlidar::Response await_response(std::uint8_t type) {
    const auto deadline = Clock::now() + laser_.options_.reply_timeout;
    while (Clock::now() < deadline) {
      read_some(deadline);
      for (auto& item : items_) {
        if (auto* response = std::get_if<ydlidar::Response>(&item);
            response && response->header.type == type) {
          ydlidar::Response found = std::move(*response);
          items_.clear();
          return found;
        }
      }
      items_.clear();
    }
    throw serial::DeviceFault("silent");
  }

  void start_scanning() {
    // A head still scanning from an earlier run answers nothing else: stop it, let the line
    // drain, then ask.
    send(ydlidar::Command::kStopScan);
    std::array<std::uint8_t, 4096> sink{};
    while (port_.read_some(sink, std::chrono::milliseconds(30)) > 0) {
    }
    parser_.reset();
    send(ydlidar::Command::kGetDeviceInfo);
    const auto info = ydlidar::decode_device_info(await_response(ydlidar::kTypeDeviceInfo).payload);
    send(ydlidar::Command::kGetHealth);
    const auto health = ydlidar::decode_health(await_response(ydlidar::kTypeHealth).payload);
    if (!info || !health) throw serial::DeviceFault("garbage");
    if (health->status >= 2) {
      spdlog::error("laser: the G4 reports error {:#06x}", health->error_code);
      throw serial::DeviceFault("refused");
    }
    spdlog::info("laser: YDLIDAR model {} firmware {}.{} hardware {} serial {}", info->model,
                 info->firmware_major, info->firmware_minor, info->hardware,
                 ydlidar::serial_number_text(*info));
    send(ydlidar::Command::kStartScan);
  }

  void run(const std::stop_token& stop) {
    const auto period = std::chrono::duration<double>(3.0 / laser_.options_.scan_rate_hz);
    auto scan_deadline =
        Clock::now() + std::chrono::duration_cast<Clock::duration>(
                           std::chrono::duration<double>(laser_.options_.spin_up_s));
    while (!stop.stop_requested()) {
      read_some(Clock::now() + std::chrono::milliseconds(20));
      for (const auto& item : items_) {
        const auto* packet = std::get_if<ydlidar::ScanPacket>(&item);
        if (packet == nullptr) continue;
        if (std::optional<ydlidar::Scan> turn = assembler_.add(*packet)) {
          publish(*turn);
          scan_deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(period);
        }
      }
      items_.clear();
      judge_checksums();
      if (Clock::now() > scan_deadline) throw serial::DeviceFault("silent");
    }
    send(ydlidar::Command::kStopScan);
  }

 private:
  void read_some(Clock::time_point deadline) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) return;
    std::array<std::uint8_t, 4096> buffer{};
    const std::size_t count = port_.read_some(buffer, left);
    laser_.health_.add_bytes(count);
    parser_.feed(std::span(buffer.data(), count), items_);
  }

  void publish(const ydlidar::Scan& turn) {
    msgs::LaserScan scan = ydlidar::to_laser_scan(turn, laser_.options_.scan, 0.0);
    laser_.health_.add_frame();
    laser_.health_.set_ok();
    for (const Listener& listener : laser_.listeners_) listener(scan, Clock::now());
    const std::lock_guard lock(laser_.mutex_);
    laser_.scan_ = std::move(scan);
  }

  // A run of packets that fail their checksum with no good one among them is a bad line, not
  // a bit flipped by chance.
  void judge_checksums() {
    const auto& stats = parser_.stats();
    const std::uint64_t new_errors = stats.checksum_errors - seen_errors_;
    if (new_errors > 0) {
      for (std::uint64_t i = 0; i < new_errors; ++i) laser_.health_.add_checksum_error();
      bad_run_ = stats.scan_packets == seen_packets_ ? bad_run_ + static_cast<int>(new_errors) : 0;
    } else if (stats.scan_packets != seen_packets_) {
      bad_run_ = 0;
    }
    seen_errors_ = stats.checksum_errors;
    seen_packets_ = stats.scan_packets;
    if (bad_run_ >= laser_.options_.bad_packets_before_fault) {
      throw serial::DeviceFault("checksum");
    }
  }

  YdlidarG4Laser& laser_;
  serial::SerialPort& port_;
  ydlidar::StreamParser parser_;
  ydlidar::ScanAssembler assembler_;
  std::vector<ydlidar::StreamItem> items_;
  std::uint64_t seen_errors_ = 0;
  std::uint64_t seen_packets_ = 0;
  int bad_run_ = 0;
};

YdlidarG4Laser::YdlidarG4Laser(YdlidarG4LaserOptions options) : options_(std::move(options)) {
  // The G4's adapter switches the motor with DTR.
  options_.serial.dtr = true;
  thread_ = std::make_unique<serial::DeviceThread>(
      options_.serial, health_,
      [this](serial::SerialPort& port, const std::stop_token& stop) { session(port, stop); });
}

YdlidarG4Laser::~YdlidarG4Laser() { stop(); }

void YdlidarG4Laser::start() { thread_->start(); }
void YdlidarG4Laser::stop() { thread_->stop(); }

std::optional<msgs::LaserScan> YdlidarG4Laser::take_scan() {
  const std::lock_guard lock(mutex_);
  return std::exchange(scan_, std::nullopt);
}

void YdlidarG4Laser::session(serial::SerialPort& port, const std::stop_token& stop) {
  Session session(*this, port);
  session.start_scanning();
  session.run(stop);
}

}  // namespace mobot::drivers::hardware
