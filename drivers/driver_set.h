#pragma once

#include <memory>
#include <optional>

#include "core/msgs/compass_reading.h"
#include "core/msgs/image.h"
#include "core/msgs/ir_ring.h"
#include "core/msgs/landmark_bearing.h"
#include "core/msgs/laser_scan.h"
#include "core/msgs/head_range.h"
#include "core/msgs/sonar_ring.h"
#include "drivers/base_driver.h"
#include "drivers/camera_info.h"
#include "drivers/pan_tilt_driver.h"
#include "drivers/sensor_driver.h"
#include "drivers/tilt_laser_driver.h"

namespace mobot::drivers {

// The devices of one robot, as the backend made them from the config. Only the base is
// mandatory; a robot without a sensor leaves it null and the stages that need it do without.
struct DriverSet {
  std::unique_ptr<BaseDriver> base;
  std::unique_ptr<SensorDriver<msgs::LaserScan>> laser;
  std::unique_ptr<SensorDriver<msgs::SonarRing>> sonar;
  std::unique_ptr<SensorDriver<msgs::IrRing>> ir;
  std::unique_ptr<SensorDriver<msgs::CompassReading>> compass;
  // The omnidirectional camera's landmark bearings (docs/algorithms.md E2, set 3).
  std::unique_ptr<SensorDriver<msgs::LandmarkBearings>> bearings;
  std::unique_ptr<SensorDriver<msgs::Image>> camera;  // JPEG frames
  std::optional<CameraInfo> camera_info;              // with a camera
  std::unique_ptr<PanTiltDriver> pan_tilt;            // a camera on a pan/tilt head (R4)
  // The ultrasonic ranger on the head, looking where the camera looks (R4).
  std::unique_ptr<SensorDriver<msgs::HeadRange>> head_range;
  std::unique_ptr<TiltLaserDriver> tilt;
};

}  // namespace mobot::drivers
