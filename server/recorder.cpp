#include "server/recorder.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "api/prometheus_text.h"

namespace mobot::server {

Recorder::Recorder(db::RunStore& runs, std::int64_t run_id, int flush_period_ms)
    : runs_(runs), run_id_(run_id), flush_period_ms_(flush_period_ms), writer_([this] { run(); }) {}

Recorder::~Recorder() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (writer_.joinable()) writer_.join();
}

void Recorder::record_pose(double t_s, double x, double y, double theta) {
  std::lock_guard lock(mutex_);
  samples_.push_back({t_s, x, y, theta});
}

void Recorder::record_event(double t_s, std::string kind, std::string detail_json) {
  std::lock_guard lock(mutex_);
  events_.push_back({t_s, std::move(kind), std::move(detail_json)});
}

void Recorder::set_distance(double distance_m) {
  std::lock_guard lock(mutex_);
  distance_m_ = distance_m;
}

void Recorder::flush() {
  std::unique_lock lock(mutex_);
  if (stopping_ && !writer_.joinable()) return;
  const std::uint64_t target = generation_ + (writing_ ? 2 : 1);
  flush_requested_ = true;
  wake_.notify_all();
  flushed_.wait(lock, [&] { return generation_ >= target || !writer_.joinable(); });
}

void Recorder::flush_async(std::function<void()> done) {
  {
    std::lock_guard lock(mutex_);
    if (!stopping_) {
      waiters_.push_back({generation_ + (writing_ ? 2 : 1), std::move(done)});
      flush_requested_ = true;
      wake_.notify_all();
      return;
    }
  }
  done();
}

void Recorder::stop(double ended_unix_s) {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (writer_.joinable()) writer_.join();
  double distance_m = 0.0;
  {
    std::lock_guard lock(mutex_);
    distance_m = distance_m_;
  }
  try {
    runs_.end_run(run_id_, ended_unix_s, distance_m);
  } catch (const std::exception& error) {
    spdlog::error("could not close run {}: {}", run_id_, error.what());
  }
}

void Recorder::run() {
  std::unique_lock lock(mutex_);
  while (true) {
    wake_.wait_for(lock, std::chrono::milliseconds(flush_period_ms_),
                   [&] { return stopping_ || flush_requested_; });
    write_batch(lock);
    if (stopping_) break;
  }
}

void Recorder::write_batch(std::unique_lock<std::mutex>& lock) {
  std::vector<db::TrajectorySample> samples;
  std::vector<db::EventRecord> events;
  samples.swap(samples_);
  events.swap(events_);
  const double distance_m = distance_m_;
  flush_requested_ = false;
  writing_ = true;
  lock.unlock();
  bool ok = true;
  if (!samples.empty() || !events.empty()) {
    try {
      runs_.append(run_id_, samples, events, distance_m);
    } catch (const std::exception& error) {
      ok = false;
      spdlog::error("recorder: writing {} samples and {} events failed: {}", samples.size(),
                    events.size(), error.what());
    }
  }
  lock.lock();
  writing_ = false;
  if (ok) {
    batches_written_ += samples.empty() && events.empty() ? 0 : 1;
    samples_written_ += samples.size();
  } else {
    // Keep the batch for the next attempt: nothing recorded is dropped on a transient error.
    ++write_failures_;
    samples.insert(samples.end(), samples_.begin(), samples_.end());
    events.insert(events.end(), events_.begin(), events_.end());
    samples_.swap(samples);
    events_.swap(events);
  }
  ++generation_;
  flushed_.notify_all();
  std::vector<Waiter> ready;
  const auto first_waiting =
      std::stable_partition(waiters_.begin(), waiters_.end(),
                            [&](const Waiter& w) { return w.generation <= generation_; });
  ready.assign(std::make_move_iterator(waiters_.begin()), std::make_move_iterator(first_waiting));
  waiters_.erase(waiters_.begin(), first_waiting);
  if (ready.empty()) return;
  lock.unlock();
  for (auto& waiter : ready) waiter.done();
  lock.lock();
}

std::string Recorder::metrics_text() const {
  std::lock_guard lock(mutex_);
  std::string out;
  api::append_metric(out, "mobot_recorder_batches_total", "counter", "Batches committed to SQLite.",
                     static_cast<double>(batches_written_));
  api::append_metric(out, "mobot_recorder_samples_total", "counter",
                     "Trajectory samples committed.", static_cast<double>(samples_written_));
  api::append_metric(out, "mobot_recorder_write_failures_total", "counter",
                     "Failed batch writes (retried).", static_cast<double>(write_failures_));
  return out;
}

}  // namespace mobot::server
