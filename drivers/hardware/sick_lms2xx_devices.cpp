#include "drivers/hardware/sick_lms2xx_devices.h"

#include <cmath>
#include <sstream>

#include "drivers/hardware/polled_sensor.h"
#include "drivers/hardware/sick_lms2xx_laser.h"

namespace mobot::drivers::hardware {
namespace {

namespace sick = protocol::sick;

class LaserDevice final : public HardwareDevice {
 public:
  explicit LaserDevice(std::unique_ptr<SickLms2xxLaser> laser) : laser_(std::move(laser)) {}
  void start() override { laser_->start(); }
  void stop() override { laser_->stop(); }
  std::vector<DeviceCounters> counters() const override { return {laser_->health().counters()}; }
  SickLms2xxLaser& laser() { return *laser_; }

 private:
  std::unique_ptr<SickLms2xxLaser> laser_;
};

sick::AngularResolution read_resolution(DeviceReader& entry) {
  double resolution_deg = 0.5;
  entry.number("resolution_deg", resolution_deg, 0.25, 1.0);
  for (const sick::AngularResolution resolution :
       {sick::AngularResolution::kQuarterDeg, sick::AngularResolution::kHalfDeg,
        sick::AngularResolution::kOneDeg}) {
    if (std::abs(resolution_deg - sick::resolution_deg(resolution)) < 1e-9) return resolution;
  }
  std::ostringstream message;
  message << entry.path() << ".resolution_deg: " << resolution_deg
          << " is no LMS resolution; it is 0.25, 0.5 or 1";
  throw BackendError(message.str());
}

}  // namespace

void make_sick_lms2xx(DeviceReader& entry, HardwareAssembly& assembly) {
  const sim::RobotProfile& profile = assembly.profile;
  if (!(profile.laser_range_max_m > 0.0)) {
    throw BackendError(entry.path() + ": this robot profile has no laser");
  }
  SickLms2xxLaserOptions options;
  options.serial = read_serial_options(entry, 38400);
  if (options.serial.baud != 38400 && options.serial.baud != 500000) {
    throw BackendError(entry.path() + ".baud: the LMS streams at 38400 or 500000 baud, not " +
                       std::to_string(options.serial.baud));
  }
  options.resolution = read_resolution(entry);
  if (options.resolution == sick::AngularResolution::kQuarterDeg && options.serial.baud != 500000) {
    throw BackendError(entry.path() +
                       ".resolution_deg: 0.25 deg comes as interlaced parts, one every mirror "
                       "rotation, which only baud: 500000 carries (38400 gives 0.5 or 1)");
  }
  entry.done();
  options.sensor_in_base = profile.laser_in_base;
  options.range_min_m = profile.laser_range_min_m;
  options.range_max_m = profile.laser_range_max_m;

  auto device =
      std::make_unique<LaserDevice>(std::make_unique<SickLms2xxLaser>(std::move(options)));
  SickLms2xxLaser& laser = device->laser();
  assembly.drivers.laser = std::make_unique<PolledSensor<msgs::LaserScan>>(
      "laser", laser.scan_rate_hz(), [&laser] { return laser.take_scan(); },
      [&laser] { return laser.status(); }, arrivals_of(laser));
  assembly.laser_source = &laser;
  assembly.devices.push_back(std::move(device));
}

}  // namespace mobot::drivers::hardware
