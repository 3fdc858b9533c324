#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <functional>
#include <string>
#include <thread>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

namespace mobot::server {

// Calls tick() at a fixed rate on a thread of its own, so network load never delays the control
// loop. Deadlines are absolute (no drift); the robot clock advances by one period per tick, so
// the time scale only changes how fast ticks come, never what they compute.
class ControlLoop {
 public:
  // `realtime_priority` 1..99 runs the loop's thread under SCHED_FIFO at that priority; 0 does not.
  ControlLoop(double period_s, std::function<void()> tick, int realtime_priority = 0);
  ~ControlLoop();
  ControlLoop(const ControlLoop&) = delete;
  ControlLoop& operator=(const ControlLoop&) = delete;

  void start(double time_scale);
  // Runs `handler` on the loop's thread, between ticks. Any thread.
  void post(std::function<void()> handler);
  // Runs the handlers posted so far on the caller's thread; only while the loop is not started.
  void run_ready();
  void set_time_scale(double time_scale);
  double time_scale() const { return time_scale_.load(); }
  void stop();
  std::string metrics_text() const;

 private:
  using Clock = std::chrono::steady_clock;
  void schedule_next();
  void on_timer();
  Clock::duration wall_period() const;

  void raise_priority();

  const double period_s_;
  const int realtime_priority_;
  std::atomic<bool> realtime_{false};
  std::function<void()> tick_;
  boost::asio::io_context io_;
  boost::asio::steady_timer timer_;
  std::thread thread_;
  std::atomic<double> time_scale_{1.0};
  Clock::time_point next_deadline_;
  bool running_ = false;

  // How late each tick started after its deadline: 0.1 ms bins up to 10 ms, the last bin open.
  static constexpr int kLatenessBins = 101;
  static constexpr double kLatenessBin_s = 1e-4;
  void note_lateness(Clock::duration lateness);
  double lateness_quantile_s(double quantile) const;
  std::array<std::atomic<std::uint64_t>, kLatenessBins> lateness_bins_{};
  std::atomic<std::int64_t> max_lateness_ns_{0};

  std::atomic<std::uint64_t> ticks_{0};
  std::atomic<std::uint64_t> late_ticks_{0};
  std::atomic<std::int64_t> max_tick_ns_{0};
  std::atomic<std::int64_t> total_tick_ns_{0};
};

}  // namespace mobot::server
