#include "drivers/hardware/dashgo_devices.h"

#include "drivers/hardware/dashgo_base.h"
#include "drivers/hardware/polled_sensor.h"
#include "drivers/hardware/sharp_ir_board.h"

namespace mobot::drivers::hardware {
namespace {

template <class Board>
class BoardDevice final : public HardwareDevice {
 public:
  explicit BoardDevice(std::unique_ptr<Board> board) : board_(std::move(board)) {}
  void start() override { board_->start(); }
  void stop() override { board_->stop(); }
  std::vector<DeviceCounters> counters() const override { return {board_->counters()}; }
  Board& board() { return *board_; }

 private:
  std::unique_ptr<Board> board_;
};

}  // namespace

void make_dashgo_arduino(DeviceReader& entry, HardwareAssembly& assembly) {
  const sim::RobotProfile& profile = assembly.profile;
  DashgoBoardOptions options;
  options.serial = read_serial_options(entry, 115200);
  entry.integer("kp", options.pid.kp, 0, 10000);
  entry.integer("kd", options.pid.kd, 0, 10000);
  entry.integer("ki", options.pid.ki, 0, 10000);
  entry.integer("ko", options.pid.ko, 1, 10000);
  entry.done();
  options.ticks_per_wheel_rev = static_cast<int>(profile.ticks_per_wheel_rev);
  options.poll_rate_hz = assembly.options.control_rate_hz;
  // Sonars and button at about 10 Hz, the battery at about 1 Hz, whatever the control rate.
  options.sonar_every = std::max(1, static_cast<int>(options.poll_rate_hz / 10.0));
  options.battery_every = std::max(1, static_cast<int>(options.poll_rate_hz));
  options.sonars_in_base = profile.sonars_in_base;
  options.sonar_cone_rad = profile.sonar_cone_rad;
  options.sonar_range_min_m = profile.sonar_range_min_m;
  options.sonar_range_max_m = profile.sonar_range_max_m;

  auto device = std::make_unique<BoardDevice<DashgoBoard>>(std::make_unique<DashgoBoard>(options));
  DashgoBoard& board = device->board();
  assembly.drivers.base = std::make_unique<DashgoBase>(board);
  if (!options.sonars_in_base.empty()) {
    assembly.drivers.sonar = std::make_unique<PolledSensor<msgs::SonarRing>>(
        "sonar", options.poll_rate_hz / options.sonar_every,
        [&board] { return board.take_sonar(); }, [&board] { return board.health().status(); });
  }
  assembly.devices.push_back(std::move(device));
}

void make_sharp_ir_arduino(DeviceReader& entry, HardwareAssembly& assembly) {
  const sim::RobotProfile& profile = assembly.profile;
  if (profile.ir_sensors_in_base.empty()) {
    throw BackendError(entry.path() + ": this robot profile has no IR ring");
  }
  SharpIrBoardOptions options;
  options.serial = read_serial_options(entry, 115200);
  options.sensors_in_base = profile.ir_sensors_in_base;
  options.cone_rad = profile.ir_cone_rad;
  options.curve = profile.ir_adc.curve;
  options.rate_hz = profile.ir_rate_hz;
  entry.number("rate_hz", options.rate_hz, 1.0, 100.0);
  for (std::size_t i = 0; i < options.sensors_in_base.size(); ++i) {
    options.pins.push_back(static_cast<int>(i));
  }
  if (const YAML::Node pins = entry.node("pins")) {
    std::vector<int> configured;
    try {
      configured = pins.as<std::vector<int>>();
    } catch (const YAML::Exception&) {
      throw BackendError(entry.path() + ".pins: expected a list of analog pin numbers");
    }
    if (configured.size() != options.sensors_in_base.size()) {
      throw BackendError(entry.path() + ".pins: one pin per sensor (" +
                         std::to_string(options.sensors_in_base.size()) + "), got " +
                         std::to_string(configured.size()));
    }
    options.pins = configured;
  }
  entry.done();
  auto device =
      std::make_unique<BoardDevice<SharpIrBoard>>(std::make_unique<SharpIrBoard>(options));
  SharpIrBoard& board = device->board();
  assembly.drivers.ir = std::make_unique<PolledSensor<msgs::IrRing>>(
      "ir", options.rate_hz, [&board] { return board.take_ring(); },
      [&board] { return board.health().status(); });
  assembly.devices.push_back(std::move(device));
}

}  // namespace mobot::drivers::hardware
