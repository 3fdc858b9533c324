#include "server/control_loop.h"

#include <pthread.h>
#include <sched.h>
#include <spdlog/spdlog.h>
#include <boost/asio/post.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "api/prometheus_text.h"

namespace mobot::server {
namespace {

// Behind by more than this many periods (a stalled machine, a debugger): skip ahead instead of
// firing a burst of catch-up ticks.
constexpr int kMaxLagPeriods = 5;

}  // namespace

ControlLoop::ControlLoop(double period_s, std::function<void()> tick, int realtime_priority)
    : period_s_(period_s),
      realtime_priority_(realtime_priority),
      tick_(std::move(tick)),
      timer_(io_) {}

ControlLoop::~ControlLoop() { stop(); }

ControlLoop::Clock::duration ControlLoop::wall_period() const {
  return std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(period_s_ / time_scale_.load()));
}

void ControlLoop::start(double time_scale) {
  time_scale_ = time_scale;
  running_ = true;
  next_deadline_ = Clock::now();
  schedule_next();
  thread_ = std::thread([this] { io_.run(); });
  raise_priority();
}

void ControlLoop::raise_priority() {
  if (realtime_priority_ <= 0) return;
  // The tick must start on time however busy the network threads are: a real-time thread is
  // scheduled before every normal one. It runs well under a millisecond per period, so it never
  // starves them. Without the privilege (not root, no CAP_SYS_NICE) the loop runs as it is.
  sched_param param{};
  param.sched_priority = realtime_priority_;
  if (const int error = pthread_setschedparam(thread_.native_handle(), SCHED_FIFO, &param)) {
    spdlog::warn("control loop: no real-time priority ({}); ticks may start late under load",
                 std::strerror(error));
    return;
  }
  realtime_ = true;
}

void ControlLoop::post(std::function<void()> handler) {
  boost::asio::post(io_, std::move(handler));
}

void ControlLoop::run_ready() {
  io_.poll();
  io_.restart();
}

void ControlLoop::set_time_scale(double time_scale) {
  boost::asio::post(io_, [this, time_scale] {
    time_scale_ = time_scale;
    next_deadline_ = Clock::now();
    timer_.cancel();
  });
}

void ControlLoop::stop() {
  if (!thread_.joinable()) return;
  boost::asio::post(io_, [this] {
    running_ = false;
    timer_.cancel();
  });
  thread_.join();
}

void ControlLoop::schedule_next() {
  next_deadline_ += wall_period();
  const auto now = Clock::now();
  if (now - next_deadline_ > kMaxLagPeriods * wall_period()) {
    late_ticks_.fetch_add(1, std::memory_order_relaxed);
    next_deadline_ = now;
  }
  timer_.expires_at(next_deadline_);
  timer_.async_wait([this](boost::system::error_code) { on_timer(); });
}

void ControlLoop::on_timer() {
  if (!running_) return;
  if (Clock::now() < next_deadline_) {
    // Re-armed by a time-scale change.
    timer_.expires_at(next_deadline_);
    timer_.async_wait([this](boost::system::error_code) { on_timer(); });
    return;
  }
  const auto started = Clock::now();
  note_lateness(started - next_deadline_);
  tick_();
  const auto elapsed_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - started).count();
  ticks_.fetch_add(1, std::memory_order_relaxed);
  total_tick_ns_.fetch_add(elapsed_ns, std::memory_order_relaxed);
  if (elapsed_ns > max_tick_ns_.load()) max_tick_ns_ = elapsed_ns;
  schedule_next();
}

void ControlLoop::note_lateness(Clock::duration lateness) {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(lateness).count();
  const auto bin = std::min<std::int64_t>(
      std::max<std::int64_t>(
          0, static_cast<std::int64_t>(static_cast<double>(ns) * 1e-9 / kLatenessBin_s)),
      kLatenessBins - 1);
  lateness_bins_[static_cast<std::size_t>(bin)].fetch_add(1, std::memory_order_relaxed);
  if (ns > max_lateness_ns_.load(std::memory_order_relaxed)) max_lateness_ns_ = ns;
}

double ControlLoop::lateness_quantile_s(double quantile) const {
  std::array<std::uint64_t, kLatenessBins> counts{};
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) total += counts[i] = lateness_bins_[i].load();
  if (total == 0) return 0.0;
  const auto wanted = static_cast<std::uint64_t>(std::ceil(quantile * static_cast<double>(total)));
  std::uint64_t seen = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    seen += counts[i];
    // The bin's upper edge: the quantile is at most this late.
    if (seen >= wanted) return static_cast<double>(i + 1) * kLatenessBin_s;
  }
  return static_cast<double>(kLatenessBins) * kLatenessBin_s;
}

std::string ControlLoop::metrics_text() const {
  const auto ticks = ticks_.load();
  const double mean_s = ticks == 0 ? 0.0 : static_cast<double>(total_tick_ns_.load()) / ticks / 1e9;
  std::string out;
  api::append_metric(out, "mobot_control_ticks_total", "counter", "Control loop ticks.",
                     static_cast<double>(ticks));
  api::append_metric(out, "mobot_control_late_ticks_total", "counter",
                     "Times the loop fell behind and skipped ahead.",
                     static_cast<double>(late_ticks_.load()));
  api::append_metric(out, "mobot_control_tick_seconds_mean", "gauge", "Mean duration of one tick.",
                     mean_s);
  api::append_metric(out, "mobot_control_tick_seconds_max", "gauge", "Longest tick.",
                     static_cast<double>(max_tick_ns_.load()) / 1e9);
  api::append_metric(out, "mobot_control_tick_lateness_seconds_p50", "gauge",
                     "Median lateness of a tick's start after its deadline (0.1 ms bins).",
                     lateness_quantile_s(0.5));
  api::append_metric(out, "mobot_control_tick_lateness_seconds_p99", "gauge",
                     "99th percentile lateness of a tick's start after its deadline (0.1 ms bins).",
                     lateness_quantile_s(0.99));
  api::append_metric(out, "mobot_control_tick_lateness_seconds_max", "gauge",
                     "Latest start of a tick after its deadline.",
                     static_cast<double>(max_lateness_ns_.load()) / 1e9);
  api::append_metric(out, "mobot_control_realtime", "gauge",
                     "The loop thread runs with real-time priority (1) or not (0).",
                     realtime_ ? 1.0 : 0.0);
  api::append_metric(out, "mobot_time_scale", "gauge", "Simulated seconds per wall second.",
                     time_scale_.load());
  return out;
}

}  // namespace mobot::server
