#include "drivers/hardware/ydlidar_devices.h"

#include "drivers/hardware/polled_sensor.h"
#include "drivers/hardware/ydlidar_g4_laser.h"

namespace mobot::drivers::hardware {
namespace {

class YdlidarDevice final : public HardwareDevice {
 public:
  explicit YdlidarDevice(YdlidarG4LaserOptions options)
      : laser_(std::make_unique<YdlidarG4Laser>(std::move(options))) {}
  void start() override { laser_->start(); }
  void stop() override { laser_->stop(); }
  std::vector<DeviceCounters> counters() const override { return {laser_->health().counters()}; }
  YdlidarG4Laser& laser() { return *laser_; }

 private:
  std::unique_ptr<YdlidarG4Laser> laser_;
};

protocol::ydlidar::SampleFormat sample_format(DeviceReader& entry) {
  std::string intensity = "none";
  entry.text("intensity", intensity);
  if (intensity == "none") return protocol::ydlidar::SampleFormat::kDistance;
  if (intensity == "8") return protocol::ydlidar::SampleFormat::kIntensity8;
  if (intensity == "10") return protocol::ydlidar::SampleFormat::kIntensity10;
  throw BackendError(entry.path() + ".intensity: '" + intensity +
                     "' is not one of none (the plain G4), 8, 10 (the SDK's intensity modes)");
}

}  // namespace

void make_ydlidar_g4(DeviceReader& entry, HardwareAssembly& assembly) {
  const sim::RobotProfile& profile = assembly.profile;
  YdlidarG4LaserOptions options;
  options.serial = read_serial_options(entry, 230400);
  options.format = sample_format(entry);
  entry.integer("bins", options.scan.bin_count, 90, 3600);
  entry.done();
  options.scan.range_min_m = profile.laser_range_min_m;
  options.scan.range_max_m = profile.laser_range_max_m;
  options.scan.sensor_in_base = profile.laser_in_base;
  options.scan_rate_hz = assembly.options.laser_rate_hz;

  auto device = std::make_unique<YdlidarDevice>(options);
  YdlidarG4Laser& laser = device->laser();
  assembly.drivers.laser = std::make_unique<PolledSensor<msgs::LaserScan>>(
      "laser", options.scan_rate_hz, [&laser] { return laser.take_scan(); },
      [&laser] { return laser.status(); }, arrivals_of(laser));
  assembly.laser_source = &laser;
  assembly.devices.push_back(std::move(device));
}

}  // namespace mobot::drivers::hardware
