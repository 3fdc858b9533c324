#include "drivers/modbus/modbus_poll_schedule.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "core/numeric/finite.h"
#include "drivers/modbus/modbus_frame_bytes.h"

namespace mobot::drivers::modbus {
namespace {

// 8N1: a start bit, 8 data bits, a stop bit.
constexpr double kBitsPerByte = 10.0;
// Due times are sums of periods that are not exact in binary.
constexpr double kSlack_s = 1e-9;

void check(const PollScheduleOptions& options) {
  std::set<int> ids;
  std::vector<int> all = options.sonar_nodes;
  all.push_back(options.compass_node);
  all.push_back(options.limit_switch_node);
  for (const int id : all) {
    // 0 is the broadcast address, which read functions do not answer; 248..255 are reserved.
    if (id < 1 || id > 247) throw std::invalid_argument("modbus poll: slave ids are 1..247");
    if (!ids.insert(id).second) throw std::invalid_argument("modbus poll: a slave id repeats");
  }
  if (options.sonar_nodes.empty()) throw std::invalid_argument("modbus poll: no sonar node");
  if (!finite_positive(options.compass_rate_hz) || !finite_positive(options.sonar_rate_hz) ||
      !finite_positive(options.limit_switch_rate_hz) || options.baud <= 0 ||
      !finite_positive(options.max_bus_load) || options.failures_before_not_ok < 1 ||
      !finite_positive(options.retry_period_s) || !std::isfinite(options.turnaround_s) ||
      options.turnaround_s < 0.0) {
    throw std::invalid_argument(
        "modbus poll: rates, baud, bus load, failure count and retry period must be positive");
  }
}

}  // namespace

std::string failure_reason(const ReadFailure& failure) {
  switch (failure.error) {
    case ReadError::kTimeout:
      return "timeout";
    case ReadError::kCrc:
      return "crc";
    case ReadError::kException:
      return "exception " + std::to_string(failure.exception_code);
    case ReadError::kBadReply:
      break;
  }
  return "bad reply";
}

ModbusPollSchedule::ModbusPollSchedule(const PollScheduleOptions& options) : options_(options) {
  check(options_);
  const double sonars = static_cast<double>(options_.sonar_nodes.size());
  requested_load_ = options_.compass_rate_hz * transaction_s(NodeKind::kCompass) +
                    sonars * options_.sonar_rate_hz * transaction_s(NodeKind::kSonar) +
                    options_.limit_switch_rate_hz * transaction_s(NodeKind::kLimitSwitch);
  rate_scale_ = std::min(1.0, options_.max_bus_load / requested_load_);

  const auto add = [this](int node, NodeKind kind, std::size_t sonar_index) {
    entries_.push_back(
        {.target = {node, kind, sonar_index}, .period_s = 1.0 / effective_rate_hz(kind)});
    NodeHealth health;
    health.node = node;
    health.kind = kind;
    health_.push_back(health);
  };
  add(options_.compass_node, NodeKind::kCompass, 0);
  for (std::size_t i = 0; i < options_.sonar_nodes.size(); ++i) {
    add(options_.sonar_nodes[i], NodeKind::kSonar, i);
  }
  add(options_.limit_switch_node, NodeKind::kLimitSwitch, 0);
  restart(0.0);
}

void ModbusPollSchedule::restart(double now_s) {
  const double sonars = static_cast<double>(options_.sonar_nodes.size());
  for (Entry& entry : entries_) {
    const double stagger =
        entry.target.kind == NodeKind::kSonar
            ? entry.period_s * static_cast<double>(entry.target.sonar_index) / sonars
            : 0.0;
    entry.phase_s = now_s + stagger;
    entry.due_s = entry.phase_s;
  }
}

std::optional<PollTarget> ModbusPollSchedule::next(double now_s) const {
  const auto earliest =
      std::min_element(entries_.begin(), entries_.end(),
                       [](const Entry& a, const Entry& b) { return a.due_s < b.due_s; });
  if (earliest->due_s > now_s + kSlack_s) return std::nullopt;
  return earliest->target;
}

double ModbusPollSchedule::next_due_s() const {
  return std::min_element(entries_.begin(), entries_.end(),
                          [](const Entry& a, const Entry& b) { return a.due_s < b.due_s; })
      ->due_s;
}

void ModbusPollSchedule::record_success(int node, double now_s) {
  const std::size_t index = index_of(node);
  NodeHealth& health = health_[index];
  ++health.reads;
  health.ok = true;
  health.reason.clear();
  health.consecutive_failures = 0;
  schedule_after(index, now_s);
}

void ModbusPollSchedule::record_failure(int node, const ReadFailure& failure, double now_s) {
  const std::size_t index = index_of(node);
  NodeHealth& health = health_[index];
  ++health.reads;
  ++health.failures;
  if (failure.error == ReadError::kTimeout) ++health.timeouts;
  if (failure.error == ReadError::kCrc) ++health.crc_errors;
  if (failure.error == ReadError::kException) ++health.exceptions;
  ++health.consecutive_failures;
  if (health.consecutive_failures >= options_.failures_before_not_ok) {
    health.ok = false;
    health.reason = failure_reason(failure);
  }
  schedule_after(index, now_s);
}

void ModbusPollSchedule::link_lost() {
  for (NodeHealth& health : health_) {
    health.ok = false;
    health.reason = "missing";
  }
}

const NodeHealth& ModbusPollSchedule::health_of(int node) const { return health_[index_of(node)]; }

double ModbusPollSchedule::transaction_s(NodeKind kind) const {
  const int reply_bytes = kind == NodeKind::kLimitSwitch ? kBitsReplyBytes : kRegisterReplyBytes;
  return (kRequestBytes + reply_bytes) * kBitsPerByte / options_.baud + options_.turnaround_s;
}

double ModbusPollSchedule::round_s() const {
  double total_s = 0.0;
  for (const Entry& entry : entries_) total_s += transaction_s(entry.target.kind);
  return total_s;
}

double ModbusPollSchedule::effective_rate_hz(NodeKind kind) const {
  switch (kind) {
    case NodeKind::kCompass:
      return options_.compass_rate_hz * rate_scale_;
    case NodeKind::kSonar:
      return options_.sonar_rate_hz * rate_scale_;
    case NodeKind::kLimitSwitch:
      break;
  }
  return options_.limit_switch_rate_hz * rate_scale_;
}

std::size_t ModbusPollSchedule::index_of(int node) const {
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    if (entries_[i].target.node == node) return i;
  }
  throw std::out_of_range("modbus poll: slave " + std::to_string(node) + " is not on the bus");
}

void ModbusPollSchedule::schedule_after(std::size_t index, double now_s) {
  Entry& entry = entries_[index];
  if (!health_[index].ok) {
    entry.due_s = now_s + options_.retry_period_s;
    return;
  }
  // The first grid slot after both the slot just served and now: a late read keeps the grid,
  // and slots missed while the bus was busy (or the node was being retried) are skipped.
  const double reference_s = std::max(entry.due_s, now_s);
  double slots = std::floor((reference_s - entry.phase_s) / entry.period_s) + 1.0;
  while (entry.phase_s + slots * entry.period_s <= reference_s + kSlack_s) slots += 1.0;
  entry.due_s = entry.phase_s + slots * entry.period_s;
}

}  // namespace mobot::drivers::modbus
