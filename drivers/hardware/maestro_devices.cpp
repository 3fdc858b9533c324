#include "drivers/hardware/maestro_devices.h"

#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/numeric/constants.h"
#include "drivers/hardware/maestro_pan_tilt.h"
#include "drivers/hardware/polled_sensor.h"

namespace mobot::drivers::hardware {
namespace {

// The head's thread, for the backend to start and stop; the driver set owns the head (its
// driver) and outlives this (the assembly's devices go first).
class MaestroDevice final : public HardwareDevice {
 public:
  explicit MaestroDevice(MaestroPanTilt& head) : head_(head) {}
  void start() override { head_.start(); }
  void stop() override { head_.stop(); }
  std::vector<DeviceCounters> counters() const override { return {head_.counters()}; }

 private:
  MaestroPanTilt& head_;
};

int read_sign(DeviceReader& entry, const std::string& key) {
  int sign = 1;
  entry.integer(key.c_str(), sign, -1, 1);
  if (sign == 0) {
    throw BackendError(entry.path() + "." + key + ": 1, or -1 for a servo whose larger pulse " +
                       "turns the joint the negative way");
  }
  return sign;
}

// One axis' channel, calibration, limits (degrees in the file) and Maestro limits.
void read_servo(DeviceReader& entry, const std::string& axis, MaestroServoOptions& servo,
                double& min_rad, double& max_rad, double& rate_rad_s, double limit_deg) {
  entry.integer((axis + "_channel").c_str(), servo.channel, 0, protocol::maestro::kChannels - 1);
  entry.number((axis + "_centre_us").c_str(), servo.calibration.centre_us,
               protocol::maestro::kMinPulse_us, protocol::maestro::kMaxPulse_us);
  entry.number((axis + "_us_per_rad").c_str(), servo.calibration.us_per_rad, 1.0, 100000.0);
  servo.calibration.sign = read_sign(entry, axis + "_sign");
  double min_deg = min_rad / kRadPerDeg;
  double max_deg = max_rad / kRadPerDeg;
  entry.number((axis + "_min_deg").c_str(), min_deg, -limit_deg, limit_deg);
  entry.number((axis + "_max_deg").c_str(), max_deg, -limit_deg, limit_deg);
  if (!(min_deg < max_deg)) {
    throw BackendError(entry.path() + "." + axis + "_max_deg: must be above " + axis + "_min_deg");
  }
  min_rad = min_deg * kRadPerDeg;
  max_rad = max_deg * kRadPerDeg;
  double speed_dps = rate_rad_s / kRadPerDeg;
  entry.number((axis + "_speed_dps").c_str(), speed_dps, 1.0, 2000.0);
  rate_rad_s = speed_dps * kRadPerDeg;
  double accel_dps2 = servo.max_accel_rad_s2 / kRadPerDeg;
  entry.number((axis + "_accel_dps2").c_str(), accel_dps2, 0.0, 100000.0);
  servo.max_accel_rad_s2 = accel_dps2 * kRadPerDeg;
}

void read_geometry(DeviceReader& entry, vision::PanTiltHeadOptions& head) {
  entry.number("l0_m", head.l0_m, 0.0, 5.0);
  entry.number("l1_m", head.l1_m, 0.0, 2.0);
  entry.number("l2_m", head.l2_m, 0.0, 2.0);
  entry.number("mount_x_m", head.mount_x_m, -2.0, 2.0);
}

// The defaults: the profile's head and ranger where it has them, with the pan limits a standard
// hobby servo turns (hobby_servo_head).
MaestroPanTiltOptions default_options(const sim::RobotProfile& profile, double& range_cone_rad) {
  MaestroPanTiltOptions options;
  range_cone_rad = sim::PanTiltCameraProfile{}.range_cone_rad;
  if (const auto& camera = profile.pan_tilt_camera) {
    const vision::PanTiltHeadOptions servos = options.head;
    options.head = camera->head;
    options.head.min_pan_rad = servos.min_pan_rad;
    options.head.max_pan_rad = servos.max_pan_rad;
    options.ranger.max_range_m = camera->range_max_m;
    range_cone_rad = camera->range_cone_rad;
  }
  return options;
}

}  // namespace

void make_pololu_maestro(DeviceReader& entry, HardwareAssembly& assembly) {
  double range_cone_rad = 0.0;
  MaestroPanTiltOptions options = default_options(assembly.profile, range_cone_rad);
  options.serial = read_serial_options(entry, 115200);
  vision::PanTiltHeadOptions& head = options.head;
  read_servo(entry, "pan", options.pan, head.min_pan_rad, head.max_pan_rad, head.max_pan_rate_rad_s,
             180.0);
  read_servo(entry, "tilt", options.tilt, head.min_tilt_rad, head.max_tilt_rad,
             head.max_tilt_rate_rad_s, 90.0);
  read_geometry(entry, head);
  int range_channel = options.range_channel.value_or(-1);
  entry.integer("range_channel", range_channel, -1, protocol::maestro::kAnalogChannels - 1);
  options.range_channel = range_channel < 0 ? std::nullopt : std::optional<int>(range_channel);
  entry.number("range_m_per_volt", options.ranger.m_per_volt, 0.01, 100.0);
  entry.number("range_max_m", options.ranger.max_range_m, 0.1, 20.0);
  double range_cone_deg = range_cone_rad / kRadPerDeg;
  entry.number("range_cone_deg", range_cone_deg, 1.0, 90.0);
  entry.number("rate_hz", options.rate_hz, 1.0, 200.0);
  int reply_timeout_ms = static_cast<int>(options.reply_timeout.count());
  entry.integer("reply_timeout_ms", reply_timeout_ms, 1, 1000);
  options.reply_timeout = std::chrono::milliseconds(reply_timeout_ms);
  entry.flag("crc", options.crc);
  entry.done();

  std::optional<CameraInfo>& camera = assembly.drivers.camera_info;
  if (!camera) {
    throw BackendError(entry.path() +
                       ": the head turns the robot's camera; configure hardware.camera as well");
  }
  if (camera->pinhole.width_px <= 0 || camera->pinhole.height_px <= 0) {
    throw BackendError(entry.path() +
                       ": a head centres targets by their pixels, so the frame size must be "
                       "known: give hardware.camera its width and height");
  }

  std::unique_ptr<MaestroPanTilt> driver;
  try {
    driver = std::make_unique<MaestroPanTilt>(options);
  } catch (const std::invalid_argument& error) {
    throw BackendError(entry.path() + "." + error.what());
  }
  MaestroPanTilt& maestro = *driver;
  camera->kind = "pan_tilt";
  camera->height_m = vision::PanTiltHead(options.head).lens_in_base({}).z_m;
  camera->range_cone_rad = options.range_channel ? range_cone_deg * kRadPerDeg : 0.0;
  if (options.range_channel) {
    assembly.drivers.head_range = std::make_unique<PolledSensor<msgs::HeadRange>>(
        "head_range", options.rate_hz, [&maestro] { return maestro.take_range(); },
        [&maestro] { return maestro.status(); });
  }
  assembly.devices.push_back(std::make_unique<MaestroDevice>(maestro));
  assembly.drivers.pan_tilt = std::move(driver);
}

}  // namespace mobot::drivers::hardware
