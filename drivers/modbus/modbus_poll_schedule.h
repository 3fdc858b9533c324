#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace mobot::drivers::modbus {

// What sits behind a slave id on R1's sensor bus; it decides the register read and its cost.
enum class NodeKind { kCompass, kSonar, kLimitSwitch };

struct PollScheduleOptions {
  int compass_node = 1;
  std::vector<int> sonar_nodes = {2, 3, 4, 5, 6, 7, 8, 9};
  int limit_switch_node = 10;
  // Each sonar is read at sonar_rate_hz; the ring's reads are spread evenly over the period, in
  // the order of sonar_nodes, so the bus carries one every 1 / (8 * rate) s instead of bursts.
  double compass_rate_hz = 10.0;
  double sonar_rate_hz = 10.0;
  double limit_switch_rate_hz = 20.0;
  // The bus's capacity: 8N1 frames are 10 bits a byte; turnaround_s is the silence around each
  // transaction (t3.5 is a fixed 1.75 ms above 19200 baud) plus the slave's reaction.
  int baud = 115200;
  double turnaround_s = 0.002;
  // When the rates would keep the bus busier than this fraction, all of them are scaled down
  // alike, so every node keeps its share instead of the last ones in line starving.
  double max_bus_load = 0.8;
  // A node is not ok after this many failed reads in a row; one good read makes it ok again.
  int failures_before_not_ok = 3;
  // A node that is not ok is tried this often instead of at its rate: every try costs a whole
  // response time-out, which would otherwise crowd out the nodes that answer.
  double retry_period_s = 0.5;
};

// Why a read gave nothing. A link failure (the device vanished) is not a node's failure; see
// ModbusPollSchedule::link_lost.
enum class ReadError { kTimeout, kCrc, kException, kBadReply };

struct ReadFailure {
  ReadError error = ReadError::kTimeout;
  int exception_code = 0;  // the Modbus exception code, for kException
};

struct NodeHealth {
  int node = 0;
  NodeKind kind = NodeKind::kSonar;
  // A node is ok until it fails failures_before_not_ok reads in a row, and again after a good
  // read. reason: "timeout", "crc", "exception N", "bad reply" or "missing" (the link is down).
  bool ok = true;
  std::string reason;
  int consecutive_failures = 0;
  std::uint64_t reads = 0;  // attempts, good or not
  std::uint64_t failures = 0;
  std::uint64_t timeouts = 0;
  std::uint64_t crc_errors = 0;
  std::uint64_t exceptions = 0;
};

// The next read to make.
struct PollTarget {
  int node = 0;
  NodeKind kind = NodeKind::kSonar;
  std::size_t sonar_index = 0;  // the position in sonar_nodes, for kSonar
};

// Which node of the sensor bus the master reads next, and what the reads say about each node's
// health. Pure: time is an argument (seconds on any monotonic clock), nothing is read or written.
// Earliest deadline first over per-node due times that stay on each node's grid (phase + k *
// period): a late read does not shift the node's later reads, and missed slots are dropped
// rather than caught up in a burst.
class ModbusPollSchedule {
 public:
  // Throws std::invalid_argument for a slave id outside 1..247, a repeated id, no sonar, or a
  // rate, baud, load, failure count or retry period that is not positive.
  explicit ModbusPollSchedule(const PollScheduleOptions& options);

  // Puts every node's first read at now_s (sonars staggered over their period), as after the
  // device was (re)opened. Health and counters stay.
  void restart(double now_s);

  // The node whose read is due at now_s (the most overdue one), or nothing when none is.
  std::optional<PollTarget> next(double now_s) const;
  // When the earliest read falls due.
  double next_due_s() const;

  // Reports the read of `node` finished at now_s; schedules the node's next read.
  void record_success(int node, double now_s);
  void record_failure(int node, const ReadFailure& failure, double now_s);
  // The device vanished: every node is not ok with reason "missing" until its next good read.
  void link_lost();

  const std::vector<NodeHealth>& health() const { return health_; }
  // Throws std::out_of_range for a node not on the bus.
  const NodeHealth& health_of(int node) const;

  // Wire time of one read of a node of `kind` (request and reply) plus the turnaround.
  double transaction_s(NodeKind kind) const;
  // One read of every node back to back.
  double round_s() const;
  // The share of the bus the configured rates ask for, before scaling.
  double requested_load() const { return requested_load_; }
  // The factor (<= 1) all rates were scaled by to stay within max_bus_load.
  double rate_scale() const { return rate_scale_; }
  // The rate a node of `kind` is read at while it is ok, after scaling.
  double effective_rate_hz(NodeKind kind) const;

  const PollScheduleOptions& options() const { return options_; }

 private:
  struct Entry {
    PollTarget target;
    double period_s = 0.0;
    double phase_s = 0.0;
    double due_s = 0.0;
  };

  std::size_t index_of(int node) const;
  void schedule_after(std::size_t index, double now_s);

  PollScheduleOptions options_;
  double requested_load_ = 0.0;
  double rate_scale_ = 1.0;
  std::vector<Entry> entries_;      // compass, sonars in ring order, limit switch
  std::vector<NodeHealth> health_;  // same order as entries_
};

// "exception 2", "timeout", ...: the reason a failure gives a node.
std::string failure_reason(const ReadFailure& failure);

}  // namespace mobot::drivers::modbus
