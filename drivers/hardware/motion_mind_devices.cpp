#include "drivers/hardware/motion_mind_devices.h"

#include <memory>
#include <stdexcept>
#include <string>

#include "drivers/hardware/motion_mind_base.h"
#include "drivers/hardware/motion_mind_line.h"
#include "drivers/hardware/motion_mind_tilt_laser.h"

namespace mobot::drivers::hardware {
namespace {

namespace mm = protocol::motion_mind;

class LineDevice final : public HardwareDevice {
 public:
  explicit LineDevice(std::shared_ptr<MotionMindLine> line) : line_(std::move(line)) {}
  void start() override { line_->start(); }
  void stop() override { line_->stop(); }
  std::vector<DeviceCounters> counters() const override { return {line_->health().counters()}; }

 private:
  std::shared_ptr<MotionMindLine> line_;
};

std::uint8_t read_address(DeviceReader& entry, const char* key, int default_address) {
  int address = default_address;
  entry.integer(key, address, 0, 255);
  if (address == mm::kBroadcastAddress) {
    throw BackendError(entry.path() + "." + key +
                       ": 99 is the broadcast address, which no board answers");
  }
  return static_cast<std::uint8_t>(address);
}

int read_sign(DeviceReader& entry, const char* key) {
  int sign = 1;
  entry.integer(key, sign, -1, 1);
  if (sign == 0) throw BackendError(entry.path() + "." + key + ": 1, or -1 for a mirrored motor");
  return sign;
}

MotionMindLine::BoardId add_board(MotionMindLine& line, const MotionMindBoardConfig& board,
                                  const std::string& key) {
  try {
    return line.add_board(board);
  } catch (const std::invalid_argument& error) {
    throw BackendError(key + ": " + error.what());
  }
}

}  // namespace

void make_motion_mind_base(DeviceReader& entry, HardwareAssembly& assembly) {
  MotionMindLineOptions options;
  options.serial = read_serial_options(entry, mm::kDefaultBaud);
  const std::uint8_t left_address = read_address(entry, "left_address", 1);
  const std::uint8_t right_address = read_address(entry, "right_address", 2);
  const int left_sign = read_sign(entry, "left_sign");
  const int right_sign = read_sign(entry, "right_sign");
  entry.done();
  if (left_address == right_address) {
    throw BackendError(entry.path() + ".right_address: the left wheel's board has " +
                       std::to_string(left_address) + " already");
  }
  options.name = "base";

  auto line = std::make_shared<MotionMindLine>(options);
  MotionMindBoardConfig wheel;
  wheel.counts_per_rev = static_cast<double>(assembly.profile.ticks_per_wheel_rev);
  wheel.setup = mm::r1_wheel_setup();
  wheel.address = left_address;
  const auto left = add_board(*line, wheel, entry.path() + ".left_address");
  wheel.address = right_address;
  const auto right = add_board(*line, wheel, entry.path() + ".right_address");

  assembly.drivers.base =
      std::make_unique<MotionMindBase>(line, left, right, left_sign, right_sign);
  // The tilt's board may join this line (the backend builds the tilt after the base).
  assembly.shared_lines[options.serial.device] = line;
  assembly.devices.push_back(std::make_unique<LineDevice>(std::move(line)));
}

void make_motion_mind_tilt(DeviceReader& entry, HardwareAssembly& assembly) {
  const sim::RobotProfile& profile = assembly.profile;
  if (!profile.has_tilt_laser) {
    throw BackendError(entry.path() + ": this robot profile has no tilting laser");
  }
  if (assembly.laser_source == nullptr) {
    throw BackendError(entry.path() +
                       ": the tilt needs the laser's scans; configure hardware.laser with a "
                       "laser whose scans it can take (the SICK LMS)");
  }
  const std::uint8_t address = read_address(entry, "address", 3);
  MotionMindTiltLaserOptions options;
  entry.number("counts_per_degree", options.counts_per_degree, 0.0, 1e6);
  if (!(options.counts_per_degree > 0.0)) {
    throw BackendError(entry.path() +
                       ".counts_per_degree: required, the quadrature counts per degree of pitch");
  }
  entry.number("home_speed_dps", options.home_speed_dps, 0.1, 90.0);
  std::string device;
  entry.text("device", device);
  const bool baud_given = static_cast<bool>(entry.node("baud"));
  double baud = mm::kDefaultBaud;
  entry.number("baud", baud, 1200, 4000000);
  entry.done();
  options.range = profile.tilt_range;
  options.sensor_in_base = profile.laser_in_base;
  options.sensor_height_m = profile.laser_height_m;

  std::shared_ptr<MotionMindLine> line;
  if (device.empty()) {
    // Only a Motion Mind base shares its line: the one line there is, if any.
    if (assembly.shared_lines.size() != 1) {
      throw BackendError(entry.path() + ".device: required unless the base is a motion_mind " +
                         "line the tilt's board shares");
    }
    line = std::static_pointer_cast<MotionMindLine>(assembly.shared_lines.begin()->second);
  } else if (const auto shared = assembly.shared_lines.find(device);
             shared != assembly.shared_lines.end()) {
    line = std::static_pointer_cast<MotionMindLine>(shared->second);
  }
  if (line) {
    if (baud_given && static_cast<unsigned>(baud) != line->options().serial.baud) {
      throw BackendError(entry.path() + ".baud: the tilt shares the base's line at " +
                         std::to_string(line->options().serial.baud) + " baud");
    }
  } else {
    MotionMindLineOptions line_options;
    line_options.serial.device = device;
    line_options.serial.baud = static_cast<unsigned>(baud);
    line_options.name = "tilt";
    line = std::make_shared<MotionMindLine>(line_options);
    assembly.devices.push_back(std::make_unique<LineDevice>(line));
  }

  const auto tilt_board = add_board(
      *line, motion_mind_tilt_board(address, options.counts_per_degree), entry.path() + ".address");
  assembly.drivers.tilt = std::make_unique<MotionMindTiltLaser>(std::move(line), tilt_board,
                                                                *assembly.laser_source, options);
}

}  // namespace mobot::drivers::hardware
