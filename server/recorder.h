#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "db/run_store.h"

namespace mobot::server {

// Writes the run's trajectory and events to SQLite off the control loop: the loop only appends to
// a buffer; a writer thread commits the buffer every flush period in one transaction. stop()
// commits what is left and closes the run.
class Recorder {
 public:
  Recorder(db::RunStore& runs, std::int64_t run_id, int flush_period_ms);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  void record_pose(double t_s, double x, double y, double theta);
  void record_event(double t_s, std::string kind, std::string detail_json);
  void set_distance(double distance_m);
  // Commits everything buffered now and returns once it is on disk.
  void flush();
  // Commits everything buffered now and calls `done` on the writer thread once it is on disk (at
  // once, on the caller's thread, when the recorder has stopped). Never blocks.
  void flush_async(std::function<void()> done);
  void stop(double ended_unix_s);

  std::int64_t run_id() const { return run_id_; }
  std::string metrics_text() const;

 private:
  void run();
  void write_batch(std::unique_lock<std::mutex>& lock);

  db::RunStore& runs_;
  const std::int64_t run_id_;
  const int flush_period_ms_;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable flushed_;
  std::vector<db::TrajectorySample> samples_;
  std::vector<db::EventRecord> events_;
  double distance_m_ = 0.0;
  bool stopping_ = false;
  bool flush_requested_ = false;
  // A batch is being written with the lock released: what is buffered now goes in the next one.
  bool writing_ = false;
  std::uint64_t batches_written_ = 0;
  std::uint64_t samples_written_ = 0;
  std::uint64_t write_failures_ = 0;
  std::uint64_t generation_ = 0;  // counts completed writes, for flush()
  struct Waiter {
    std::uint64_t generation;
    std::function<void()> done;
  };
  std::vector<Waiter> waiters_;  // flush_async() callers, oldest first
  std::thread writer_;
};

}  // namespace mobot::server
