#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <stop_token>
#include <string>
#include <thread>
#include <vector>

#include "drivers/device_status.h"
#include "drivers/modbus/modbus_poll_schedule.h"

// libmodbus's context, declared the way modbus.h does: its header defines macros such as ON and
// OFF that would leak into everything including this one.
typedef struct _modbus modbus_t;

namespace mobot::drivers::modbus {

// R1's RS-485 sensor bus: the PC is the Modbus RTU master (through the dsPIC30F4011 bridge, which
// drives the transceiver) of ten slave nodes. The register map:
//   compass (CMPS03)   input register 0 = heading in tenths of a degree, 0..3599, clockwise from
//                      magnetic north
//   each sonar (SRF05) input register 0 = range to the nearest echo in millimetres (3 cm - 4 m,
//                      22.5 degree cone); 0 = no echo
//   limit switch       discrete input 0 = 1 while pressed
// The master reads them with functions 4 (read input registers) and 2 (read discrete inputs).
struct ModbusRtuBusOptions {
  std::string device_path;  // the serial port, e.g. "/dev/ttyUSB0" or a udev symlink
  int baud = 115200;        // 8N1
  int compass_node = 1;
  std::vector<int> sonar_nodes = {2, 3, 4, 5, 6, 7, 8, 9};
  int limit_switch_node = 10;
  double compass_rate_hz = 10.0;
  double sonar_rate_hz = 10.0;  // each sonar, read round robin
  double limit_switch_rate_hz = 20.0;

  // heading_rad = wrap(heading_offset_rad - compass_rad): the compass counts clockwise and the
  // map counter-clockwise, so the sign flips, and heading_offset_rad is the map-frame heading
  // (counter-clockwise from the map's x axis) at which the compass reads 0, i.e. where magnetic
  // north lies in the map, corrected by the compass's mounting error. pi/2 for a map whose x
  // axis points east and y axis to magnetic north.
  double heading_offset_rad = 0.0;

  // How long a read waits for the whole reply. A reply takes under 1 ms at 115200 baud; the rest
  // is the bridge's and the kernel's latency.
  double response_timeout_s = 0.02;
  // A node is not ok after this many failed reads in a row and is then only retried every
  // retry_period_s (a silent node costs a whole time-out per try).
  int failures_before_not_ok = 3;
  double retry_period_s = 0.5;
  // The bus is "silent" (or "crc", when replies came but failed their CRC) after this long
  // without a good reply from any node.
  double silent_timeout_s = 0.5;
  // While the device cannot be opened it is tried again this often.
  double reopen_period_s = 0.5;
  // Puts a UART with a kernel RS-485 driver into RS-485 mode (TIOCSRS485). R1's bridge drives
  // the transceiver itself, so its port stays RS-232.
  bool rs485_mode = false;
  // Bus capacity used by the schedule; see PollScheduleOptions.
  double turnaround_s = 0.002;
  double max_bus_load = 0.8;
};

using BusClock = std::chrono::steady_clock;

// The newest reading of a node, when it came, and how many good readings the node gave so far
// (a consumer that remembers the count knows whether the reading is new).
struct CompassSample {
  double heading_rad = 0.0;  // map frame, counter-clockwise, (-pi, pi]
  BusClock::time_point received;
  std::uint64_t count = 0;
};

struct SonarSample {
  std::optional<double> range_m;  // nothing: no echo within the sonar's range
  BusClock::time_point received;
  std::uint64_t count = 0;
};

struct LimitSwitchSample {
  bool pressed = false;
  BusClock::time_point received;
  std::uint64_t count = 0;
};

// For /metrics. libmodbus does not show the bytes it moves, so transactions are counted.
struct ModbusBusCounters {
  std::uint64_t requests = 0;
  std::uint64_t replies = 0;  // frames that passed the CRC, exceptions included
  // The length of the complete replies received, good or with a bad CRC: a lower bound of the
  // bytes the port received (stray bytes and cut replies are not seen).
  std::uint64_t reply_bytes = 0;
  std::uint64_t exceptions = 0;
  std::uint64_t crc_errors = 0;
  std::uint64_t timeouts = 0;
  std::uint64_t bad_replies = 0;  // another slave's, the wrong length or function, a bad value
  std::uint64_t link_errors = 0;  // reads or writes that found the device gone
  std::uint64_t open_failures = 0;
  std::uint64_t reconnects = 0;  // successful opens after the first
};

// The master of the sensor bus: owns the libmodbus RTU context and a thread that reads the nodes
// as ModbusPollSchedule says and keeps the newest readings, each node's health and the bus's
// status. The getters are thread-safe and never block on the bus. The thread never throws: a
// device that cannot be opened or vanishes (the port unplugged) is reopened every
// reopen_period_s.
class ModbusRtuBus {
 public:
  // Throws std::invalid_argument for an empty device path, a baud the serial port does not know,
  // a time-out outside (0, 60) s, a period that is not positive, or options the schedule
  // rejects.
  explicit ModbusRtuBus(const ModbusRtuBusOptions& options);
  ~ModbusRtuBus();
  ModbusRtuBus(const ModbusRtuBus&) = delete;
  ModbusRtuBus& operator=(const ModbusRtuBus&) = delete;

  // Starts the thread (a no-op while it runs); stop() joins it and closes the device.
  void start();
  void stop();

  std::optional<CompassSample> compass() const;
  // In the order of options().sonar_nodes; nothing for a sonar not read yet.
  std::vector<std::optional<SonarSample>> sonars() const;
  std::optional<LimitSwitchSample> limit_switch() const;
  std::vector<NodeHealth> node_health() const;
  // ok, or why not: "stopped", "missing" (the device cannot be opened), "starting" (opened, no
  // reply yet), "silent" (no node answered for silent_timeout_s), "crc" (replies came in that
  // time but all failed their CRC).
  DeviceStatus status() const;
  ModbusBusCounters counters() const;
  // The counters in the form every real device gives /metrics: frames are the replies,
  // checksum errors the CRC failures and replies that did not parse, bytes reply_bytes.
  DeviceCounters device_counters(std::string name) const;
  // The schedule's estimate of one read of every node back to back: the bytes at the baud and
  // the turnaround of each.
  double round_s() const;
  // The rate the schedule really reads nodes of `kind` at: a slow baud scales every rate down to
  // fit the line.
  double effective_rate_hz(NodeKind kind) const;

  const ModbusRtuBusOptions& options() const { return options_; }

 private:
  enum class Link { kStopped, kMissing, kOpen };
  struct ContextFree {
    void operator()(modbus_t* context) const;
  };

  void run(const std::stop_token& stop);
  bool open();
  void close(bool lost);
  // One read of `target`; false when the device is gone.
  bool read(const PollTarget& target);
  // What a read brought, under the lock: a register's word or an input's bit.
  void take_reply(const PollTarget& target, std::uint16_t word, bool bit, BusClock::time_point now);
  void take_failure(const PollTarget& target, const ReadFailure& failure, BusClock::time_point now);
  // Waits until `deadline` or a stop request.
  void wait_until(const std::stop_token& stop, BusClock::time_point deadline);
  double seconds(BusClock::time_point time) const;

  const ModbusRtuBusOptions options_;
  const BusClock::time_point epoch_;
  std::unique_ptr<modbus_t, ContextFree> context_;  // the bus thread's alone while it runs

  mutable std::mutex mutex_;
  std::condition_variable_any wake_;
  ModbusPollSchedule schedule_;
  std::optional<CompassSample> compass_;
  std::vector<std::optional<SonarSample>> sonars_;
  std::optional<LimitSwitchSample> limit_switch_;
  ModbusBusCounters counters_;
  Link link_ = Link::kStopped;
  bool opened_before_ = false;
  BusClock::time_point opened_at_;
  std::optional<BusClock::time_point> last_reply_at_;
  std::optional<BusClock::time_point> last_crc_error_at_;

  std::jthread thread_;  // last: stopped and joined before the state it uses goes
};

}  // namespace mobot::drivers::modbus
