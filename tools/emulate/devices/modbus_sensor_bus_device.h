#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <random>
#include <set>
#include <span>
#include <string_view>
#include <vector>

#include "core/geometry/pose2d.h"
#include "tools/emulate/emulated_device.h"
#include "tools/emulate/emulated_world.h"

namespace mobot::emulate {

// CRC-16/MODBUS (reflected polynomial 0xA001, initial 0xFFFF). A frame carries it low byte first.
std::uint16_t modbus_crc16(std::span<const std::uint8_t> bytes);

// Cuts a master's requests out of the byte stream a slave hears. RTU frames have no delimiter
// but silence, which a byte stream with coarse time stamps does not show reliably; instead a
// request is recognised by its function's length (8 bytes for functions 1-6 and 8, 4 for 7, 11,
// 12 and 17, 10 for 22, by the byte count for 15, 16 and 23) and a matching CRC. After garbage or a
// spoiled request, the earliest position where a whole valid request starts wins and the bytes
// before it are dropped; a request of an unknown function cannot be framed and is dropped.
class ModbusRtuRequestFramer {
 public:
  // Appends `bytes` and returns the requests they completed, in order, CRC included.
  std::vector<std::vector<std::uint8_t>> push(std::span<const std::uint8_t> bytes);

  // Bytes dropped as not part of any valid request.
  std::uint64_t discarded_bytes() const { return discarded_bytes_; }
  std::size_t buffered_bytes() const { return buffer_.size(); }

 private:
  std::vector<std::uint8_t> buffer_;
  std::uint64_t discarded_bytes_ = 0;
};

// R1's sensor bus as the PC's master sees it (the register map ModbusRtuBus reads, see
// drivers/modbus/modbus_rtu_bus.h):
//   compass (CMPS03)  input register 0 = heading in tenths of a degree, 0..3599, clockwise from
//                     north (the CMPS03's convention)
//   each sonar (SRF05) input register 0 = range to the nearest echo in millimetres, 30..4000;
//                     0 = no echo within 4 m
//   limit switch      discrete input 0 = 1 while pressed
// Function 3 (holding registers) reads the same table as function 4. A read outside a node's
// table gets exception 2 (illegal data address), a quantity of 0 or above the function's limit
// exception 3, another framed function exception 1. An absent node, a broadcast and a request
// with a bad CRC get no reply.
struct ModbusSensorBusOptions {
  int baud = 115200;
  int compass_node = 1;
  std::vector<int> sonar_nodes = {2, 3, 4, 5, 6, 7, 8, 9};
  int limit_switch_node = 10;
  // The silence between the request's last byte and the reply's first one; nothing: t3.5 of
  // the RTU spec (3.5 byte times, fixed 1.75 ms above 19200 baud).
  std::optional<double> reply_delay_s;

  // The map-frame heading (counter-clockwise from the map's x axis) at which the compass reads
  // 0; the driver's heading_offset_rad, the same number, turns it back.
  double heading_offset_rad = 0.0;
  double compass_noise_rad = 0.01745329251994329577;  // 1 degree

  // Mounting poses in the base frame, in the order of sonar_nodes.
  std::vector<geometry::Pose2D> sonar_poses = {
      {0.30, 0.20, 0.78539816339744830962},   {0.30, 0.07, 0.26179938779914943654},
      {0.30, -0.07, -0.26179938779914943654}, {0.30, -0.20, -0.78539816339744830962},
      {0.15, 0.30, 1.57079632679489661923},   {-0.15, 0.30, 1.57079632679489661923},
      {0.15, -0.30, -1.57079632679489661923}, {-0.15, -0.30, -1.57079632679489661923}};
  double sonar_height_m = 0.4;
  double sonar_cone_rad = 0.39269908169872415481;  // 22.5 degrees, full opening
  // The nearest of this many rays spread evenly across the cone (an odd count keeps the axis).
  int sonar_rays = 5;
  double sonar_min_m = 0.03;  // nearer echoes read as this
  double sonar_max_m = 4.0;
  double sonar_noise_fraction = 0.02;  // standard deviation, relative to the range
};

// The slave nodes of R1's RS-485 sensor bus, byte for byte: frames the master's requests, checks
// their CRC, samples the world when a request is complete and answers after the RTU silence,
// one byte every 10 bit times of the baud. Not thread-safe: one emulator thread drives it.
class ModbusSensorBusDevice : public EmulatedDevice {
 public:
  // `world` must outlive the device. Throws std::invalid_argument for a slave id outside
  // 1..247 or repeated, a sonar pose count unlike the sonar count, a baud, ray count or range
  // that is not positive, or negative noise.
  ModbusSensorBusDevice(const EmulatedWorld& world, const ModbusSensorBusOptions& options,
                        std::uint64_t seed);

  std::string_view name() const override { return "modbus_sensor_bus"; }
  void receive(std::span<const std::uint8_t> bytes, double now_s) override;
  std::vector<std::uint8_t> transmit(double now_s) override;
  void set_bad_checksums(bool on) override { bad_checksums_ = on; }

  // An absent node hears nothing and says nothing (unplugged, or its supply failed). Throws
  // std::invalid_argument for a slave id not on the bus.
  void set_node_present(int node, bool present);
  void set_limit_switch(bool pressed) { limit_switch_pressed_ = pressed; }

  // Requests framed with a valid CRC, whoever they were for.
  std::uint64_t requests() const { return requests_; }
  std::uint64_t replies() const { return replies_; }
  std::uint64_t discarded_bytes() const { return framer_.discarded_bytes(); }
  const ModbusSensorBusOptions& options() const { return options_; }

 private:
  struct TimedByte {
    double due_s = 0.0;
    std::uint8_t byte = 0;
  };

  std::optional<std::vector<std::uint8_t>> answer(std::span<const std::uint8_t> request);
  std::uint16_t compass_register();
  std::uint16_t sonar_register(std::size_t sonar);
  void queue_reply(std::vector<std::uint8_t> reply, double now_s);

  const EmulatedWorld& world_;
  ModbusSensorBusOptions options_;
  std::mt19937_64 rng_;
  double byte_s_;
  double reply_delay_s_;
  ModbusRtuRequestFramer framer_;
  std::deque<TimedByte> outgoing_;
  double now_s_ = 0.0;
  double line_free_s_ = 0.0;  // when the last queued reply byte has gone out
  std::set<int> absent_nodes_;
  bool limit_switch_pressed_ = false;
  bool bad_checksums_ = false;
  std::uint64_t requests_ = 0;
  std::uint64_t replies_ = 0;
};

}  // namespace mobot::emulate
