#include "drivers/hardware/sick_lms2xx_laser.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include <spdlog/spdlog.h>

#include "drivers/protocol/sick_lms2xx_scan.h"

namespace mobot::drivers::hardware {
namespace {

namespace sick = protocol::sick;
using Clock = std::chrono::steady_clock;

constexpr double kMirrorRate_hz = 75.0;
// Reads are this short at most, so a stop request is noticed within one.
constexpr std::chrono::milliseconds kReadSlice{20};
constexpr std::size_t kReadBufferBytes = 4096;
// Grace for a write beyond the time its bytes take on the line.
constexpr double kWriteSlack_s = 0.1;
// Bytes around the values of a measured-values telegram: header, command, count word, status,
// CRC.
constexpr std::size_t kScanOverheadBytes = sick::kHeaderBytes + 1 + 2 + 1 + sick::kCrcBytes;
// An interlaced part covers 180 deg at 1 deg steps; the first part has the extra beam.
constexpr std::size_t kValuesPerPart = 181;

// Thrown inside a session when the thread is asked to stop, so every wait unwinds to the
// session, which says goodbye to the LMS and returns.
struct Stopped {};

Clock::duration to_duration(double seconds) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

bool interlaced(sick::AngularResolution resolution) {
  return resolution == sick::AngularResolution::kQuarterDeg;
}

// 0.25 deg over 180 deg is no variant of its own: it is the 100 deg / 0.25 deg variant streamed as
// interlaced 180 deg parts (mode 0x2A).
sick::Variant variant_for(sick::AngularResolution resolution) {
  if (interlaced(resolution)) return {sick::ScanAngle::k100Deg, resolution};
  return {sick::ScanAngle::k180Deg, resolution};
}

std::size_t values_per_telegram(sick::AngularResolution resolution) {
  return interlaced(resolution) ? kValuesPerPart : sick::values_per_scan(variant_for(resolution));
}

}  // namespace

double sick_lms2xx_scan_rate_hz(unsigned baud_bps, sick::AngularResolution resolution) {
  const std::size_t telegram_bytes = kScanOverheadBytes + 2 * values_per_telegram(resolution);
  const double busy_rotations =
      sick::transmission_time_s(telegram_bytes, static_cast<int>(baud_bps)) * kMirrorRate_hz;
  // A telegram is ready every `ready_every` rotations (a complete scan of 2 or 4 interlaced
  // rotations, or one part each rotation); the ones that find the line busy are skipped.
  const int ready_every = interlaced(resolution) ? 1 : sick::rotations_per_scan(resolution);
  const double waits = std::max(1.0, std::ceil(busy_rotations / ready_every));
  const double telegram_rate_hz = kMirrorRate_hz / (waits * ready_every);
  return interlaced(resolution) ? telegram_rate_hz / sick::rotations_per_scan(resolution)
                                : telegram_rate_hz;
}

// The host's end of the line in one session: writes requests, and hands on what the telegram
// parser finds one event at a time, counting bytes, frames and bad CRCs in the health.
class SickLms2xxLaser::Line {
 public:
  Line(serial::SerialPort& port, serial::DeviceHealth& health, int bad_crc_limit,
       std::stop_token stop)
      : port_(port),
        health_(health),
        bad_crc_limit_(bad_crc_limit),
        stop_(std::move(stop)),
        buffer_(kReadBufferBytes) {}

  void send(std::span<const std::uint8_t> telegram) {
    const double line_s = sick::transmission_time_s(telegram.size(), static_cast<int>(baud_bps()));
    port_.write_all(telegram, std::chrono::ceil<std::chrono::milliseconds>(
                                  std::chrono::duration<double>(line_s + kWriteSlack_s)));
  }

  // The next event, or nothing once `deadline` passed without one. Throws Stopped when the
  // thread is asked to stop, DeviceFault("checksum") after bad_crc_limit bad CRCs in a row.
  std::optional<sick::StreamEvent> next(Clock::time_point deadline) {
    while (pending_.empty()) {
      if (stop_.stop_requested()) throw Stopped{};
      const Clock::time_point now = Clock::now();
      if (now >= deadline) return std::nullopt;
      const auto wait = std::clamp(std::chrono::ceil<std::chrono::milliseconds>(deadline - now),
                                   std::chrono::milliseconds(1), kReadSlice);
      const std::size_t count = port_.read_some(buffer_, wait);
      if (count == 0) continue;
      last_bytes_at_ = Clock::now();
      health_.add_bytes(count);
      for (sick::StreamEvent& event : stream_.feed(std::span(buffer_.data(), count))) {
        pending_.push_back({std::move(event), last_bytes_at_});
      }
    }
    Pending pending = std::move(pending_.front());
    pending_.pop_front();
    received_at_ = pending.at;
    if (pending.event.kind == sick::StreamEvent::Kind::kBadCrc) {
      health_.add_checksum_error();
      if (++bad_crc_in_row_ >= bad_crc_limit_) throw serial::DeviceFault("checksum");
    } else if (pending.event.kind == sick::StreamEvent::Kind::kTelegram) {
      health_.add_frame();
      bad_crc_in_row_ = 0;
    }
    return std::move(pending.event);
  }

  // Follows the LMS to another rate: what was buffered at the old one is noise now.
  void set_baud(unsigned baud_bps) {
    port_.set_baud(baud_bps);
    stream_.reset();
    pending_.clear();
  }
  unsigned baud_bps() const { return port_.options().baud; }

  int bad_crc_in_row() const { return bad_crc_in_row_; }
  // When the last bytes came (the epoch before any did).
  Clock::time_point last_bytes_at() const { return last_bytes_at_; }
  // When the bytes that completed the last event came.
  Clock::time_point received_at() const { return received_at_; }
  // For the goodbye after a stop request: its waits run to their ends.
  void ignore_stop() { stop_ = {}; }

 private:
  struct Pending {
    sick::StreamEvent event;
    Clock::time_point at;
  };

  serial::SerialPort& port_;
  serial::DeviceHealth& health_;
  int bad_crc_limit_;
  std::stop_token stop_;
  sick::TelegramStream stream_;
  std::vector<std::uint8_t> buffer_;
  std::deque<Pending> pending_;
  int bad_crc_in_row_ = 0;
  Clock::time_point last_bytes_at_;
  Clock::time_point received_at_;
};

struct SickLms2xxLaser::Exchange {
  std::optional<sick::Telegram> reply;  // the expected reply or 0x92
  bool nak = false;                     // the LMS got the request damaged
  bool heard = false;                   // a telegram with a good CRC came: it talks at this rate
};

SickLms2xxLaser::SickLms2xxLaser(SickLms2xxLaserOptions options) : options_(std::move(options)) {
  const unsigned baud = options_.serial.baud;
  if (baud != 38400 && baud != 500000) {
    throw std::invalid_argument("sick lms2xx: it streams at 38400 or 500000 baud, not " +
                                std::to_string(baud));
  }
  if (interlaced(options_.resolution) && baud != 500000) {
    throw std::invalid_argument(
        "sick lms2xx: 0.25 deg comes as interlaced parts, one every mirror rotation, which only "
        "500000 baud carries");
  }
  scan_rate_hz_ = sick_lms2xx_scan_rate_hz(baud, options_.resolution);
  values_per_telegram_ = values_per_telegram(options_.resolution);
  // An LMS talks 9600 baud after power-on: the line opens there and follows the LMS.
  serial::SerialOptions line = options_.serial;
  line.baud = 9600;
  thread_ = std::make_unique<serial::DeviceThread>(
      line, health_,
      [this](serial::SerialPort& port, const std::stop_token& stop) { session(port, stop); });
}

SickLms2xxLaser::~SickLms2xxLaser() { stop(); }

void SickLms2xxLaser::start() { thread_->start(); }
void SickLms2xxLaser::stop() { thread_->stop(); }

std::optional<msgs::LaserScan> SickLms2xxLaser::take_scan() {
  const std::lock_guard lock(mutex_);
  return std::exchange(newest_, std::nullopt);
}

void SickLms2xxLaser::add_listener(Listener listener) { listeners_.push_back(std::move(listener)); }

void SickLms2xxLaser::session(serial::SerialPort& port, const std::stop_token& stop) {
  Line line(port, health_, options_.bad_crc_limit, stop);
  try {
    set_up(line);
    stream(line);
  } catch (const Stopped&) {
    say_goodbye(line);
  }
}

void SickLms2xxLaser::refused(const std::string& why) {
  if (why != last_complaint_) spdlog::warn("{}: {}", health_.name(), why);
  last_complaint_ = why;
  throw serial::DeviceFault("refused");
}

SickLms2xxLaser::Exchange SickLms2xxLaser::exchange(Line& line,
                                                    std::span<const std::uint8_t> telegram,
                                                    std::uint8_t reply_command) const {
  Exchange result;
  line.send(telegram);
  const Clock::time_point sent_at = Clock::now();
  // A telegram the LMS is sending goes out before its ACK: the wait for the ACK lasts while
  // bytes keep coming, up to the time of the longest telegram.
  const double longest_s =
      sick::transmission_time_s(sick::kMaxTelegramBytes, static_cast<int>(line.baud_bps()));
  const Clock::time_point ack_limit = sent_at + to_duration(options_.ack_timeout_s + longest_s);
  std::optional<Clock::time_point> acked_at;
  for (;;) {
    const Clock::time_point deadline =
        acked_at ? *acked_at + to_duration(options_.reply_timeout_s + longest_s)
                 : std::min(ack_limit, std::max(sent_at, line.last_bytes_at()) +
                                           to_duration(options_.ack_timeout_s));
    if (Clock::now() >= deadline) return result;
    std::optional<sick::StreamEvent> event = line.next(deadline);
    if (!event) continue;  // bytes may have come meanwhile, extending the wait for the ACK
    switch (event->kind) {
      case sick::StreamEvent::Kind::kAck:
        if (!acked_at) acked_at = Clock::now();
        break;
      case sick::StreamEvent::Kind::kNak:
        if (!acked_at) {
          result.nak = true;
          return result;
        }
        break;
      case sick::StreamEvent::Kind::kBadCrc:
        // After the ACK it was most likely the reply, damaged: the request is sent again.
        if (acked_at) return result;
        break;
      case sick::StreamEvent::Kind::kTelegram: {
        result.heard = true;
        const std::uint8_t command = event->telegram.command();
        if (command == reply_command || command == sick::kNotAcknowledgedReply) {
          result.reply = std::move(event->telegram);
          return result;
        }
        break;  // a scan streamed before the request took effect
      }
    }
  }
}

sick::Telegram SickLms2xxLaser::request(Line& line, std::span<const std::uint8_t> telegram,
                                        std::uint8_t reply_command, const std::string& what) {
  bool nak = false;
  for (int attempt = 0; attempt < options_.request_tries; ++attempt) {
    Exchange result = exchange(line, telegram, reply_command);
    if (result.reply) {
      if (result.reply->command() == sick::kNotAcknowledgedReply) {
        refused("the LMS does not take the " + what + " request");
      }
      return std::move(*result.reply);
    }
    nak = nak || result.nak;
  }
  if (nak) refused("the LMS keeps answering the " + what + " request with NAK");
  throw serial::DeviceFault("silent");
}

std::optional<sick::StatusReply> SickLms2xxLaser::probe(Line& line) {
  std::vector<unsigned> rates{last_baud_bps_};
  for (const sick::BaudRate rate : {sick::BaudRate::k9600, sick::BaudRate::k19200,
                                    sick::BaudRate::k38400, sick::BaudRate::k500000}) {
    const auto bps = static_cast<unsigned>(sick::bits_per_second(rate));
    if (bps != last_baud_bps_) rates.push_back(bps);
  }
  const std::vector<std::uint8_t> status_request = sick::status_request();
  for (const unsigned bps : rates) {
    line.set_baud(bps);
    // Stray ACK or NAK bytes are what noise at a wrong rate looks like: only a telegram with a
    // good CRC shows the rate is the LMS's.
    Exchange first = exchange(line, status_request, sick::kStatusReply);
    if (!first.reply && !first.heard) continue;
    const sick::Telegram reply = first.reply
                                     ? std::move(*first.reply)
                                     : request(line, status_request, sick::kStatusReply, "status");
    if (reply.command() == sick::kNotAcknowledgedReply) {
      refused("the LMS does not take the status request");
    }
    last_baud_bps_ = bps;
    return sick::parse_status_reply(reply);
  }
  throw serial::DeviceFault("silent");
}

void SickLms2xxLaser::set_up(Line& line) {
  const std::optional<sick::StatusReply> found = probe(line);
  const auto switch_mode = [&](const std::vector<std::uint8_t>& telegram, const std::string& what) {
    const std::optional<sick::ModeSwitchReply> reply =
        sick::parse_mode_switch_reply(request(line, telegram, sick::kModeSwitchReply, what));
    if (!reply || !reply->accepted()) {
      refused("the LMS does not switch to " + what);
    }
  };

  // The rate the line found and the one the LMS says it talks agree on a real line; trusting
  // either alone would skip the switch when they do not (a line that ignores its rate).
  const unsigned wanted_bps = options_.serial.baud;
  const bool other_rate =
      found && found->baud_bps > 0 && found->baud_bps != static_cast<int>(wanted_bps);
  if (line.baud_bps() != wanted_bps || other_rate) {
    const std::optional<sick::BaudRate> rate =
        sick::baud_rate_from_bps(static_cast<int>(wanted_bps));
    switch_mode(sick::baud_rate_request(*rate), std::to_string(wanted_bps) + " baud");
    // The LMS answered at the old rate and talks the new one from now on.
    line.set_baud(wanted_bps);
    last_baud_bps_ = wanted_bps;
  }
  // In case an earlier session left it streaming: the set-up's replies need a quiet line.
  switch_mode(sick::mode_switch_request(sick::OperatingMode::kOnRequest), "on-request mode");

  const sick::Variant wanted = variant_for(options_.resolution);
  const std::optional<sick::VariantReply> variant = sick::parse_variant_reply(
      request(line, sick::variant_request(wanted), sick::kVariantReply, "variant"));
  if (!variant || !variant->accepted || variant->variant() != wanted) {
    std::ostringstream why;
    why << "the LMS does not take the variant " << static_cast<int>(wanted.angle) << " deg at "
        << sick::resolution_deg(wanted.resolution) << " deg";
    refused(why.str());
  }

  const std::optional<sick::StatusReply> status =
      sick::parse_status_reply(request(line, sick::status_request(), sick::kStatusReply, "status"));
  if (status) {
    range_bits_ = sick::range_bits_for_measuring_mode(status->measuring_mode);
    if (range_bits_ == 0) {
      std::ostringstream why;
      why << "the LMS is set to measuring mode 0x" << std::hex
          << static_cast<int>(status->measuring_mode) << ", which sends no ranges";
      refused(why.str());
    }
  } else {
    // Older firmware's short status block: the factory measuring mode is the likely one.
    range_bits_ = 13;
    if (last_complaint_ != "short status") {
      spdlog::warn("{}: unreadable status block; assuming 13-bit ranges", health_.name());
    }
    last_complaint_ = "short status";
  }

  switch_mode(sick::mode_switch_request(interlaced(options_.resolution)
                                            ? sick::OperatingMode::kContinuousPartialScans
                                            : sick::OperatingMode::kContinuousAllValues),
              "continuous output");
}

void SickLms2xxLaser::stream(Line& line) {
  const bool parts = interlaced(options_.resolution);
  sick::InterlacedScanAssembler assembler(options_.resolution);
  sick::LaserScanOptions scan_options;
  scan_options.sensor_in_base = options_.sensor_in_base;
  scan_options.range_min_m = options_.range_min_m;
  scan_options.range_max_m = options_.range_max_m;
  scan_options.range_bits = range_bits_;
  const Clock::duration silence =
      to_duration(std::max(3.0 / scan_rate_hz_, options_.min_silence_s));
  Clock::time_point last_scan_at = Clock::now();
  for (;;) {
    std::optional<sick::StreamEvent> event = line.next(last_scan_at + silence);
    if (!event) {
      // Telegrams came but each failed its CRC: the line is the trouble, not a silent laser.
      throw serial::DeviceFault(line.bad_crc_in_row() > 0 ? "checksum" : "silent");
    }
    if (event->kind != sick::StreamEvent::Kind::kTelegram ||
        event->telegram.command() != sick::kMeasuredValuesReply) {
      continue;  // a late reply, or a stray ACK
    }
    const std::optional<sick::MeasuredValues> values =
        sick::decode_measured_values(event->telegram);
    if (!values) {
      health_.add_checksum_error();
      continue;
    }
    // A telegram of another shape (the LMS reconfigured behind the driver's back) is no scan
    // of this configuration; if only such come, the laser turns silent and is set up again.
    if (values->partial_scan != parts ||
        (!parts && values->values.size() != values_per_telegram_)) {
      continue;
    }
    const std::optional<sick::MeasuredValues> complete = parts ? assembler.add(*values) : values;
    if (!complete) continue;
    std::optional<msgs::LaserScan> scan = sick::to_laser_scan(*complete, scan_options);
    if (!scan) {
      health_.add_checksum_error();
      continue;
    }
    // The mirror finished the scan before the telegram took its time on the line.
    const std::size_t telegram_bytes =
        sick::kHeaderBytes + event->telegram.payload.size() + sick::kCrcBytes;
    const double on_line_s =
        sick::transmission_time_s(telegram_bytes, static_cast<int>(line.baud_bps()));
    publish(std::move(*scan), line.received_at() - to_duration(on_line_s));
    last_scan_at = Clock::now();
    health_.set_ok();
    last_complaint_.clear();  // a complaint that comes back after this is news again
  }
}

void SickLms2xxLaser::say_goodbye(Line& line) {
  // Best effort: a streaming LMS left alone keeps the line busy for whoever opens it next.
  line.ignore_stop();
  try {
    exchange(line, sick::mode_switch_request(sick::OperatingMode::kOnRequest),
             sick::kModeSwitchReply);
  } catch (const serial::SerialError&) {
  } catch (const serial::DeviceFault&) {
  }
}

void SickLms2xxLaser::publish(msgs::LaserScan scan, Clock::time_point measured_at) {
  for (const Listener& listener : listeners_) listener(scan, measured_at);
  const std::lock_guard lock(mutex_);
  newest_ = std::move(scan);
}

}  // namespace mobot::drivers::hardware
