#include "server/control_loop.h"

#include <boost/asio/post.hpp>

#include "api/prometheus_text.h"

namespace mobot::server {
namespace {

// Behind by more than this many periods (a stalled machine, a debugger): skip ahead instead of
// firing a burst of catch-up ticks.
constexpr int kMaxLagPeriods = 5;

}  // namespace

ControlLoop::ControlLoop(double period_s, std::function<void()> tick)
    : period_s_(period_s), tick_(std::move(tick)), timer_(io_) {}

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
  tick_();
  const auto elapsed_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - started).count();
  ticks_.fetch_add(1, std::memory_order_relaxed);
  total_tick_ns_.fetch_add(elapsed_ns, std::memory_order_relaxed);
  if (elapsed_ns > max_tick_ns_.load()) max_tick_ns_ = elapsed_ns;
  schedule_next();
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
  api::append_metric(out, "mobot_time_scale", "gauge", "Simulated seconds per wall second.",
                     time_scale_.load());
  return out;
}

}  // namespace mobot::server
