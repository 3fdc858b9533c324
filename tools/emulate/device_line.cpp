#include "tools/emulate/device_line.h"

#include <time.h>

#include <array>
#include <map>

namespace mobot::emulate {

std::optional<LineFault> line_fault_named(const std::string& name) {
  static const std::map<std::string, LineFault> kFaults{
      {"drop", LineFault::kDrop},       {"stall", LineFault::kStall},
      {"garbage", LineFault::kGarbage}, {"checksum", LineFault::kChecksum},
      {"unplug", LineFault::kUnplug},
  };
  const auto found = kFaults.find(name);
  if (found == kFaults.end()) return std::nullopt;
  return found->second;
}

DeviceLine::DeviceLine(std::unique_ptr<EmulatedDevice> device, std::filesystem::path link_path,
                       std::uint64_t seed)
    : device_(std::move(device)), port_(std::move(link_path)), rng_(seed) {}

void DeviceLine::set_fault(LineFault fault, double now_s, double duration_s) {
  clear_fault();
  fault_ = fault;
  fault_until_s_ = duration_s > 0.0 ? now_s + duration_s : 0.0;
  if (fault == LineFault::kChecksum) device_->set_bad_checksums(true);
  if (fault == LineFault::kUnplug) port_.unplug();
}

void DeviceLine::clear_fault() {
  if (fault_ == LineFault::kChecksum) device_->set_bad_checksums(false);
  if (fault_ == LineFault::kUnplug) port_.plug();
  fault_ = LineFault::kNone;
}

void DeviceLine::step(double now_s) {
  if (fault_ != LineFault::kNone && fault_until_s_ > 0.0 && now_s >= fault_until_s_) clear_fault();
  const double elapsed_s = now_s - last_step_s_;
  last_step_s_ = now_s;
  if (fault_ == LineFault::kStall || fault_ == LineFault::kUnplug) return;

  std::array<std::uint8_t, 4096> buffer{};
  for (std::size_t count = port_.read(buffer); count > 0; count = port_.read(buffer)) {
    device_->receive(std::span(buffer.data(), count), now_s);
  }
  std::vector<std::uint8_t> out = device_->transmit(now_s);
  const std::uint64_t out_begin = model_offset_;
  const std::size_t model_bytes = out.size();
  model_offset_ += model_bytes;
  if (fault_ == LineFault::kDrop) {
    settle_marks(out_begin, model_bytes, 0);
    return;
  }
  if (fault_ == LineFault::kGarbage) {
    // Noise at about the device's own pace (and some even when it has nothing to say).
    out.resize(std::max(out.size(), static_cast<std::size_t>(elapsed_s * 2000.0)));
    std::uniform_int_distribution<int> byte(0, 255);
    for (std::uint8_t& value : out) value = static_cast<std::uint8_t>(byte(rng_));
  }
  const std::size_t written = port_.write(out);
  // Noise carries none of the model's bytes.
  settle_marks(out_begin, model_bytes, fault_ == LineFault::kGarbage ? 0 : written);
}

void DeviceLine::set_mark_listener(std::function<void(std::int64_t realtime_us)> written) {
  mark_written_ = std::move(written);
}

void DeviceLine::add_output_mark(std::uint64_t end_offset) { marks_.push_back(end_offset); }

void DeviceLine::settle_marks(std::uint64_t begin, std::size_t size, std::size_t written) {
  std::optional<std::int64_t> now_us;
  while (!marks_.empty() && marks_.front() <= begin + size) {
    if (marks_.front() <= begin + written && mark_written_) {
      if (!now_us) {
        timespec now{};
        clock_gettime(CLOCK_REALTIME, &now);
        now_us = std::int64_t{now.tv_sec} * 1'000'000 + now.tv_nsec / 1000;
      }
      mark_written_(*now_us);
    }
    marks_.pop_front();
  }
}

}  // namespace mobot::emulate
