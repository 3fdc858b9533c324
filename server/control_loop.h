#pragma once

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
  ControlLoop(double period_s, std::function<void()> tick);
  ~ControlLoop();
  ControlLoop(const ControlLoop&) = delete;
  ControlLoop& operator=(const ControlLoop&) = delete;

  void start(double time_scale);
  void set_time_scale(double time_scale);
  double time_scale() const { return time_scale_.load(); }
  void stop();
  std::string metrics_text() const;

 private:
  using Clock = std::chrono::steady_clock;
  void schedule_next();
  void on_timer();
  Clock::duration wall_period() const;

  const double period_s_;
  std::function<void()> tick_;
  boost::asio::io_context io_;
  boost::asio::steady_timer timer_;
  std::thread thread_;
  std::atomic<double> time_scale_{1.0};
  Clock::time_point next_deadline_;
  bool running_ = false;

  std::atomic<std::uint64_t> ticks_{0};
  std::atomic<std::uint64_t> late_ticks_{0};
  std::atomic<std::int64_t> max_tick_ns_{0};
  std::atomic<std::int64_t> total_tick_ns_{0};
};

}  // namespace mobot::server
